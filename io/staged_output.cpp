#include "io/staged_output.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hexmesh {

namespace fs = std::filesystem;

std::function<void(const char* step)> StagedOutput::commit_step_hook;

namespace {

std::string host_name() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "host";
    return name;
}

// The prefix of the staging folders of `outdir` on this host: .NAME.staging-HOST- beside it.
fs::path staging_prefix(const fs::path& outdir, const std::string& host) {
    const fs::path absolute = fs::absolute(outdir).lexically_normal();
    const fs::path folder = absolute.has_filename() ? absolute : absolute.parent_path();
    return folder.parent_path() / ("." + folder.filename().string() + ".staging-" + host + "-");
}

// Removes the staging folders of `outdir` left by runs on this host that were killed before
// they could clean up (their process is gone): a killed refinement can leave gigabytes.
// Folders of other hosts (a shared file system) and of live processes stay.
void remove_stale_staging(const fs::path& prefix) {
    std::error_code ec;
    const std::string start = prefix.filename().string();
    for (const auto& entry : fs::directory_iterator(prefix.parent_path(), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(start, 0) != 0) continue;
        const std::string digits = name.substr(start.size());
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stoll(digits));
        if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
        std::error_code ignored;
        fs::remove_all(entry.path(), ignored);
    }
}

// `from` (a file or a folder) recreated at `to` by hard links, or copies where links fail.
void carry(const fs::path& from, const fs::path& to) {
    std::error_code ec;
    if (fs::is_directory(from, ec)) {
        fs::create_directory(to, ec);
        for (const auto& entry : fs::directory_iterator(from))
            carry(entry.path(), to / entry.path().filename());
        return;
    }
    fs::create_hard_link(from, to, ec);
    if (ec) fs::copy(from, to, fs::copy_options::copy_symlinks);
}

void step(const char* name) {
    if (StagedOutput::commit_step_hook) StagedOutput::commit_step_hook(name);
}

}  // namespace

StagedOutput::StagedOutput(std::string outdir, Scope scope)
    : outdir_(std::move(outdir)), scope_(scope) {
    std::error_code ec;
    // A link to a folder: the folder takes the result (the link stays as the user made it).
    if (fs::is_symlink(outdir_, ec) && fs::is_directory(outdir_, ec))
        outdir_ = fs::canonical(outdir_, ec).string();
    if (fs::exists(outdir_, ec) && !fs::is_directory(outdir_, ec))
        throw std::runtime_error(fmt::format("{}: exists and is not a directory", outdir_));
    created_outdir_ = fs::create_directories(outdir_, ec);
    if (ec)
        throw std::runtime_error(
            fmt::format("{}: cannot create directory ({})", outdir_, ec.message()));
    if (scope_ == Scope::whole_folder) {
        lock_fd_ = ::open(outdir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (lock_fd_ < 0 || ::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
            const int error = errno;
            if (lock_fd_ >= 0) ::close(lock_fd_), lock_fd_ = -1;
            if (created_outdir_) fs::remove(outdir_, ec);
            throw std::runtime_error(
                error == EWOULDBLOCK
                    ? fmt::format("{}: another hexmesh process is writing into this folder; "
                                  "wait for it or choose another one",
                                  outdir_)
                    : fmt::format("{}: cannot lock the folder ({})", outdir_,
                                  std::strerror(error)));
        }
    }
    const fs::path prefix = scope_ == Scope::whole_folder
                                ? staging_prefix(outdir_, host_name())
                                : fs::path(outdir_) / (".staging-" + host_name() + "-");
    remove_stale_staging(prefix);
    staging_ = prefix.string() + std::to_string(::getpid());
    fs::remove_all(staging_, ec);
    fs::create_directories(staging_, ec);
    if (ec) {
        if (lock_fd_ >= 0) ::close(lock_fd_), lock_fd_ = -1;
        if (created_outdir_) fs::remove(outdir_, ec);
        throw std::runtime_error(fmt::format("{}: cannot write {} it ({})", outdir_,
                                             scope_ == Scope::whole_folder ? "beside" : "into",
                                             ec.message()));
    }
}

StagedOutput::~StagedOutput() {
    std::error_code ec;
    fs::remove_all(staging_, ec);
    if (!committed_ && created_outdir_) fs::remove_all(outdir_, ec);
    if (lock_fd_ >= 0) ::close(lock_fd_);
}

std::string StagedOutput::path(const std::string& name) {
    names_.push_back(name);
    return (fs::path(staging_) / name).string();
}

void StagedOutput::write_text(const std::string& name, const std::string& text) {
    const std::string file = path(name);
    std::ofstream out(file);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(fmt::format("{}: cannot write {}", outdir_, name));
}

std::vector<std::string> StagedOutput::commit() {
    std::error_code ec;
    // Each staged entry in place by one rename (a .vtm's pieces folder is one entry).
    const auto move_entries = [&] {
        for (const auto& entry : fs::directory_iterator(staging_)) {
            const fs::path target = fs::path(outdir_) / entry.path().filename();
            fs::remove_all(target, ec);
            fs::rename(entry.path(), target, ec);
            if (ec)
                throw std::runtime_error(fmt::format("{}: cannot move output into place ({})",
                                                     target.string(), ec.message()));
        }
    };
    if (scope_ == Scope::named_entries) {
        move_entries();
    } else {
        // What the folder holds that this run does not write stays.
        std::vector<fs::path> carried;
        for (const auto& entry : fs::directory_iterator(outdir_)) {
            const fs::path target = fs::path(staging_) / entry.path().filename();
            if (entry.path().filename().string().rfind(".staging-", 0) != 0 &&
                !fs::exists(target, ec))
                carry(entry.path(), target), carried.push_back(target);
        }
        step("carried");
        if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, outdir_.c_str(), RENAME_EXCHANGE) ==
            0) {
            step("exchanged");
            fs::remove_all(staging_, ec);  // the old contents now
        } else if (errno == EINVAL || errno == ENOSYS || errno == EOPNOTSUPP || errno == EBUSY ||
                   errno == EXDEV) {
            // No atomic exchange here (a file system without it, the current folder, a mount
            // point): the written entries move one by one; the carried copies go.
            for (const fs::path& copy : carried) fs::remove_all(copy, ec);
            move_entries();
        } else {
            throw std::runtime_error(fmt::format("{}: cannot move the output into place ({})",
                                                 outdir_, std::strerror(errno)));
        }
    }
    std::vector<std::string> finals;
    for (const std::string& name : names_) finals.push_back((fs::path(outdir_) / name).string());
    committed_ = true;
    return finals;
}

}  // namespace hexmesh

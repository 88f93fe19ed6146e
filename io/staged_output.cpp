#include "io/staged_output.h"

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include <cerrno>
#include <csignal>

namespace hexmesh {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "host";
    return name;
}

// Removes the staging folders in `outdir` left by runs on this host that were killed before
// they could clean up (their process is gone): a killed refinement can leave gigabytes.
// Folders of other hosts (a shared file system) and of live processes stay.
void remove_stale_staging(const std::string& outdir, const std::string& host) {
    const std::string prefix = ".staging-" + host + "-";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(outdir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        const std::string digits = name.substr(prefix.size());
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stoll(digits));
        if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
        std::error_code ignored;
        fs::remove_all(entry.path(), ignored);
    }
}

}  // namespace

StagedOutput::StagedOutput(std::string outdir) : outdir_(std::move(outdir)) {
    std::error_code ec;
    if (fs::exists(outdir_, ec) && !fs::is_directory(outdir_, ec))
        throw std::runtime_error(fmt::format("{}: exists and is not a directory", outdir_));
    created_outdir_ = fs::create_directories(outdir_, ec);
    if (ec) throw std::runtime_error(fmt::format("{}: cannot create directory ({})", outdir_, ec.message()));
    const std::string host = host_name();
    if (!created_outdir_) remove_stale_staging(outdir_, host);
    staging_ = (fs::path(outdir_) / fmt::format(".staging-{}-{}", host, ::getpid())).string();
    fs::create_directories(staging_, ec);
    if (ec) {
        if (created_outdir_) fs::remove(outdir_, ec);
        throw std::runtime_error(fmt::format("{}: cannot write into directory", outdir_));
    }
}

StagedOutput::~StagedOutput() {
    std::error_code ec;
    fs::remove_all(staging_, ec);
    if (!committed_ && created_outdir_) fs::remove_all(outdir_, ec);
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
    std::vector<std::string> finals;
    std::error_code ec;
    // Everything the writers put in staging moves, including side folders (a .vtm's pieces).
    for (const auto& entry : fs::directory_iterator(staging_)) {
        const fs::path target = fs::path(outdir_) / entry.path().filename();
        fs::remove_all(target, ec);
        fs::rename(entry.path(), target, ec);
        if (ec) throw std::runtime_error(fmt::format("{}: cannot move output into place ({})", target.string(), ec.message()));
    }
    for (const std::string& name : names_) finals.push_back((fs::path(outdir_) / name).string());
    committed_ = true;
    return finals;
}

}  // namespace hexmesh

// Runs the hexmesh executable (or any command) and captures its exit code and output.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace hexmesh::test_support {

struct CommandResult {
    int exit_code = -1;
    std::string out, err;
};

inline std::string read_text(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Runs `command` through the shell in the source tree, stdout and stderr captured apart.
// The scratch paths handed out in this test process, removed (files or folders) when it exits
// unless a test failed.
class ScratchRegistry {
public:
    // gtest's UnitTest is made first so that it outlives this registry (asked at exit).
    ScratchRegistry() { ::testing::UnitTest::GetInstance(); }
    void add(const std::filesystem::path& path) { paths_.insert(path); }
    ~ScratchRegistry() {
        // A failed test's files stay for a look (their paths are in its messages).
        if (::testing::UnitTest::GetInstance()->Failed()) return;
        std::error_code ignored;
        for (const std::filesystem::path& path : paths_) std::filesystem::remove_all(path, ignored);
    }

private:
    std::set<std::filesystem::path> paths_;
};

inline ScratchRegistry& scratch_registry() {
    static ScratchRegistry registry;
    return registry;
}

// A scratch path private to this test process (ctest runs tests in parallel processes),
// removed with whatever it holds when the process exits.
inline std::filesystem::path scratch(const std::string& name) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("hexmesh_e2e_" + std::to_string(::getpid()) + "_" + name);
    scratch_registry().add(path);
    return path;
}

inline CommandResult run_command(const std::string& command) {
    const auto out = scratch("stdout.txt"), err = scratch("stderr.txt");
    const std::string full = "cd '" HEXMESH_SOURCE_DIR "' && " + command + " > '" + out.string() +
                             "' 2> '" + err.string() + "' < /dev/null";
    const int status = std::system(full.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(out);
    r.err = read_text(err);
    return r;
}

inline CommandResult run_hexmesh(const std::string& arguments) {
    return run_command(std::string("'") + HEXMESH_EXE + "' " + arguments);
}

inline int count_lines(const std::string& text) {
    int n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

// The last word of the table row starting with `name` in `out`, if there is such a row.
inline std::optional<std::string> row_last_word(const std::string& out, const std::string& name) {
    const auto at = out.find("  " + name + " ");
    if (at == std::string::npos) return std::nullopt;
    const auto end = out.find('\n', at);
    const std::string line = out.substr(at, end - at);
    return line.substr(line.find_last_of(' ') + 1);
}

// The integer printed on the table row starting with `name`, or -1.
inline long long row_value(const std::string& out, const std::string& name) {
    const auto word = row_last_word(out, name);
    return word ? std::stoll(*word) : -1;
}

// The number printed on the table row starting with `name`, or -1.
inline double real_value(const std::string& out, const std::string& name) {
    const auto word = row_last_word(out, name);
    return word ? std::stod(*word) : -1;
}

}  // namespace hexmesh::test_support

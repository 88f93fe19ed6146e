// Runs the hexmesh executable (or any command) and captures its exit code and output.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "tests/scratch_registry.h"

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

// A scratch path private to this test process (ctest runs tests in parallel processes),
// removed with whatever it holds when the process exits.
inline std::filesystem::path scratch(const std::string& name) {
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("hexmesh_e2e_" + std::to_string(::getpid()) + "_" + name);
    return test::remove_at_exit(path);
}

// Runs `command` through the shell in the source tree, stdout and stderr captured apart.
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

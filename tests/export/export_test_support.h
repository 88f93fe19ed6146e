// Shared helpers of the exporter tests: small grids, scratch folders, running tools.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "hexmesh/core/block_grid.h"
#include "surface/analytic.h"
#include "volume/o_h_grid.h"

namespace hexmesh::test_export {

namespace fs = std::filesystem;

// The scratch folders of this test process, removed when it exits unless a test failed.
class ScratchRegistry {
public:
    // gtest's UnitTest is made first so that it outlives this registry (asked at exit).
    ScratchRegistry() { ::testing::UnitTest::GetInstance(); }
    void add(const fs::path& dir) { dirs_.insert(dir); }
    ~ScratchRegistry() {
        // A failed test's files stay for a look (their paths are in its messages).
        if (::testing::UnitTest::GetInstance()->Failed()) return;
        std::error_code ignored;
        for (const fs::path& dir : dirs_) fs::remove_all(dir, ignored);
    }

private:
    std::set<fs::path> dirs_;
};

inline ScratchRegistry& scratch_registry() {
    static ScratchRegistry registry;
    return registry;
}

// A fresh scratch folder private to this test process (removed when the process exits).
inline fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() /
                         ("hexmesh_test_export_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    scratch_registry().add(dir);
    return dir;
}

// The O-H grid of the unit sphere: 7 blocks, wall patch on the 6 outer blocks' kmax faces.
inline BlockGrid small_o_h_grid(int cells_per_edge = 4, int wall_cells = 3) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions o;
    o.cells_per_edge = cells_per_edge;
    o.wall_cells = wall_cells;
    return make_o_h_grid(sphere, o);
}

struct ToolRun {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};

// Runs a shell command, capturing its output; exit_code -1 if it could not run.
inline ToolRun run_tool(const std::string& command) {
    ToolRun r;
    std::FILE* pipe = ::popen((command + " 2>&1 < /dev/null").c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline bool have_tool(const std::string& name) {
    return run_tool("command -v " + name).exit_code == 0;
}

}  // namespace hexmesh::test_export

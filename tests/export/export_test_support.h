// Shared helpers of the exporter tests: small grids, scratch folders, running tools.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "hexmesh/core/block_grid.h"
#include "surface/analytic.h"
#include "tests/scratch_registry.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"

namespace hexmesh::test_export {

namespace fs = std::filesystem;

// A fresh scratch folder private to this test process (removed when the process exits).
inline fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() /
                         ("hexmesh_test_export_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return test::remove_at_exit(dir);
}

// The O-H grid of the unit sphere: 7 blocks, wall patch on the 6 outer blocks' kmax faces.
inline BlockGrid small_o_h_grid(int cells_per_edge = 4, int wall_cells = 3) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions o;
    o.cells_per_edge = cells_per_edge;
    o.wall_cells = wall_cells;
    return make_o_h_grid(sphere, o);
}

// The exterior O-grid of the unit sphere (six blocks): patches wall and farfield.
inline BlockGrid small_o_grid(int cells_per_edge = 4, int layers = 5, double far_field_size = 5) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OGridOptions o;
    o.cells_per_edge = cells_per_edge;
    o.layers = layers;
    o.far_field_size = far_field_size;
    return make_o_grid(sphere, o);
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

// The number after `label` in checkMesh's output, or NaN.
inline double number_after(const std::string& text, const std::string& label) {
    const auto at = text.find(label);
    if (at == std::string::npos) return std::nan("");
    return std::strtod(text.c_str() + at + label.size(), nullptr);
}

// An OpenFOAM command line, with WM_PROJECT_DIR pointing at Debian's OpenFOAM etc/ folder when
// the environment has not set it (the package's binaries need it and nothing else).
inline std::string openfoam_command(const std::string& command) {
    if (!std::getenv("WM_PROJECT_DIR") && fs::exists("/usr/share/openfoam/etc/controlDict"))
        return "WM_PROJECT_DIR=/usr/share/openfoam " + command;
    return command;
}

inline std::string check_mesh_command(const fs::path& case_dir) {
    return openfoam_command("checkMesh -case '" + case_dir.string() + "'");
}

}  // namespace hexmesh::test_export

#include "hexmesh/pipeline/measure_file.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/optimize_tet_mesh.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/grid_meter.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/case_file.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"

namespace hexmesh {
namespace {

// The report of `grid` against the body and wall law of the case file `sidecar`, else ("")
// its cells alone; `settings` as in hex_file_report.
GridReport block_grid_report(const BlockGrid& grid, const std::string& sidecar,
                             std::string* settings) {
    if (settings) settings->clear();
    if (sidecar.empty()) {
        GridReport report;
        report.quality = measure_quality(grid);
        return report;
    }
    const Case c = read_case(sidecar);
    const Body body = make_body(c.geometry);
    const std::optional<TriangleSurface> surface = reference_surface(c.geometry);
    if (settings) *settings = case_to_json(c);
    return measure_grid(grid, *body, wall_layers(c), surface ? &*surface : nullptr);
}

}  // namespace

bool is_block_grid_file(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".vtm" || ext == ".vts";
}

std::string case_of_grid(const std::string& grid_path, const std::string& case_path) {
    if (!case_path.empty()) return case_path;
    const std::filesystem::path beside =
        std::filesystem::path(grid_path).parent_path() / "grid.case.json";
    return std::filesystem::exists(beside) ? beside.string() : std::string();
}

std::optional<TetMesh> read_tet_mesh(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".vtu" && ext != ".vtk") return std::nullopt;
    VolumeMesh m = read_volume_mesh(path);
    if (m.num_tets() == 0 || m.num_hexes() > 0) return std::nullopt;
    return TetMesh{std::move(m.points), std::move(m.tets)};
}

double tet_boundary_distance(const TetMesh& mesh, const std::string& case_path) {
    const Case c = read_case(case_path);
    const Body body = make_body(c.geometry);
    const double h = tet_sizes(c, *body).wall;
    return max_boundary_distance(mesh, case_boundary(c, body, h)) / h;
}

GridReport hex_file_report(const std::string& path, const std::string& case_path,
                           std::string* settings) {
    const std::string sidecar =
        is_block_grid_file(path) ? case_of_grid(path, case_path) : std::string();
    if (!sidecar.empty()) return block_grid_report(read_vtk_block_grid(path), sidecar, settings);
    if (!case_path.empty()) throw InputError("--case is for block grids (.vtm .vts)");
    if (settings) settings->clear();
    const HexMesh mesh = read_vtk_mesh(path);
    GridReport report;
    report.quality = naming_file(path, [&] { return measure_quality(mesh); });
    return report;
}

ReportPage page_of_mesh(const std::string& path, const std::string& case_path) {
    if (!std::filesystem::exists(path))
        throw InputError(fmt::format("{}: no such mesh file", path));
    if (const auto tets = read_tet_mesh(path))
        return tet_mesh_report_page(path, *tets, measure_tet_quality(*tets));
    if (is_block_grid_file(path)) {
        const BlockGrid grid = read_vtk_block_grid(path);
        std::string settings;
        const GridReport report = block_grid_report(grid, case_of_grid(path, case_path), &settings);
        return grid_report_page(path, report, draw_grid(grid), settings);
    }
    if (!case_path.empty()) throw InputError("--case is for block grids (.vtm .vts)");
    const HexMesh mesh = read_vtk_mesh(path);
    return hex_mesh_report_page(path, mesh,
                                naming_file(path, [&] { return measure_quality(mesh); }));
}

}  // namespace hexmesh

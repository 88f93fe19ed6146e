#include "hexmesh/pipeline/run_case.h"

#include <chrono>
#include <cmath>
#include <fmt/format.h>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/make_body.h"
#include "io/export_grid.h"
#include "io/staged_output.h"
#include "io/vtk_mesh.h"
#include "volume/o_h_grid.h"
#include "volume/single_block_grid.h"

namespace hexmesh {
namespace {

class PhaseTimer {
public:
    explicit PhaseTimer(std::ostream& log) : log_(log) {}
    void done(const std::string& what) {
        const auto now = std::chrono::steady_clock::now();
        log_ << fmt::format("  {:<40}{:8.2f} s\n", what,
                            std::chrono::duration<double>(now - start_).count());
        start_ = now;
    }

private:
    std::ostream& log_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

WallLayers wall_layers(const Case& c) {
    if (!c.boundary_layer) return {};
    return {c.boundary_layer->first_height, c.boundary_layer->growth_ratio,
            c.boundary_layer->layers};
}

}  // namespace

BlockGrid build_grid(const Case& c, const ImplicitFunction& body) {
    if (c.grid.topology == "single-block") {
        SingleBlockOptions o;
        o.cells = c.grid.cells;
        o.wall_layers = wall_layers(c);
        o.centre = c.grid.center;
        return make_single_block_grid(body, o);
    }
    OHGridOptions o;
    o.cells_per_edge = c.grid.cells_per_edge;
    o.wall_cells = c.grid.wall_cells;
    o.core_size = c.grid.core_size;
    o.wall_layers = wall_layers(c);
    o.centre = c.grid.center;
    return make_o_h_grid(body, o);
}

GridReport measure_grid(const BlockGrid& grid, const ImplicitFunction& body) {
    const HexMesh mesh = to_hex_mesh(grid);
    GridReport report;
    report.quality = measure_quality(mesh);

    // h: mean length of the hex edges whose two ends lie on the wall.
    double length = 0;
    Id edges = 0;
    for (Id cell = 0; cell < mesh.num_cells(); ++cell)
        for (const auto& e : hex_edges) {
            const Id a = mesh.node(cell, e[0]), b = mesh.node(cell, e[1]);
            if (grid.kinds[a] == VertexKind::slip && grid.kinds[b] == VertexKind::slip) {
                length += (mesh.points[a] - mesh.points[b]).norm();
                ++edges;
            }
        }
    if (edges == 0) return report;
    const double h = length / edges;
    double worst = 0;
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip)
            worst = std::max(worst, std::abs(body.value(grid.points[v])));
    report.length_scale = h;
    report.max_surface_distance = worst / h;
    return report;
}

RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log) {
    PhaseTimer timer(log);
    const Body body = make_body(c.geometry);
    timer.done("geometry");
    RunResult result;
    result.grid = build_grid(c, *body);
    timer.done(fmt::format("grid ({}, {} blocks, {} cells)", c.grid.topology,
                           result.grid.blocks.size(), result.grid.num_cells()));
    result.report = measure_grid(result.grid, *body);
    timer.done("quality");

    const Id inverted = result.report.quality.inverted_cells;
    if (inverted > 0 && !options.keep_invalid) {
        throw std::runtime_error(fmt::format(
            "{}: the grid has {} inverted cells (min scaled Jacobian {:.3g}); nothing written "
            "(use --keep-invalid to write it as grid_invalid.*)",
            c.path, inverted, result.report.quality.min_scaled_jacobian));
    }
    const std::string stem = inverted > 0 ? "grid_invalid" : "grid";
    StagedOutput out(outdir);
    write_vtk_grid(result.grid, out.path(stem + (result.grid.blocks.size() == 1 ? ".vts" : ".vtm")));
    for (const std::string& format : c.outputs)  // the VTK grid above is always written
        if (format != "vtk")
            write_grid_format(result.grid, format, out.path(export_file_name(format, stem, result.grid)));
    out.write_text("quality.json", quality_json(result.report));
    result.files = out.commit();
    timer.done("write");
    return result;
}

}  // namespace hexmesh

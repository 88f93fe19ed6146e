#include "hexmesh/pipeline/refine_family.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hexmesh/core/quality.h"
#include "hexmesh/pipeline/optimize_grid.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"
#include "volume/refine.h"

namespace hexmesh {
namespace {

// A length scale for projection tolerances: the edge of a cube of the grid's mean cell volume,
// estimated from the bounding box (only its order of magnitude matters).
double cell_length_scale(const BlockGrid& grid) {
    Box3 box{grid.points.front(), grid.points.front()};
    for (const Vec3& p : grid.points) {
        box.lo = box.lo.cwiseMin(p);
        box.hi = box.hi.cwiseMax(p);
    }
    const double cells = std::max<double>(1, double(grid.num_cells()));
    return box.diagonal() / std::cbrt(cells);
}

// The functional's box targets can pull a cell below the quality interpolation gave it (at
// the irregular corners of the O-H core, where the coarse cell is no box). Where the polish
// leaves a cell below `floor`, the worst scaled Jacobian of the interpolated grid, its new
// nodes go back to their interpolated (and projected) positions, until no cell is below it.
// Only cells with a node the polish could move (not `held`) are checked: the others are as
// they were. The projected grid itself meets the floor, so this ends. Skipped when
// interpolation left inverted cells (floor <= 0): then the polish is the untangling.
void keep_no_worse_than(BlockGrid& grid, const std::vector<Vec3>& projected, double floor,
                        const std::vector<bool>& held, Id first_new) {
    if (!(floor > 0)) return;
    for (int round = 0; round < 100; ++round) {
        bool reverted = false;
        for (const Block& block : grid.blocks)
            for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
                if (std::all_of(nodes.begin(), nodes.end(), [&](Id v) { return bool(held[v]); })) return;
                std::array<Vec3, 8> p;
                for (int k = 0; k < 8; ++k) p[k] = grid.points[nodes[k]];
                if (hex_scaled_jacobian(p) >= floor) return;
                for (Id v : nodes)
                    if (v >= first_new && grid.points[v] != projected[v]) {
                        grid.points[v] = projected[v];
                        reverted = true;
                    }
            });
        if (!reverted) return;
    }
}

}  // namespace

RefinementResult refine_on_body(const BlockGrid& coarse, const ImplicitFunction& body,
                                const RefinementOptions& options) {
    RefinementResult result;
    result.grid = refine_grid(coarse);
    BlockGrid& grid = result.grid;
    const Id first_new = static_cast<Id>(coarse.points.size());
    const Id count = static_cast<Id>(grid.points.size());
    const double h = cell_length_scale(grid);

    std::vector<double> moved(count, -1.0);
    tbb::parallel_for(first_new, count, [&](Id v) {
        const VertexKind kind = grid.kinds[v];
        if (kind != VertexKind::slip && kind != VertexKind::feature_edge) return;
        Vec3 p = grid.points[v];
        if (kind == VertexKind::slip) {
            ProjectionOptions o;
            o.tolerance = 1e-12;
            p = project_to_surface(body, p, h, o).point;
        } else {
            p = project_to_crease(body, p, h);
        }
        moved[v] = (p - grid.points[v]).norm();
        grid.points[v] = p;
    });
    for (Id v = first_new; v < count; ++v)
        if (moved[v] >= 0) {
            ++result.projected;
            result.max_projection = std::max(result.max_projection, moved[v]);
        }

    // Free: the new nodes of the cells that touch a new wall node (the interpolated interior
    // is as smooth as the coarse grid and stays as it is); held: everything else.
    std::vector<bool> held(count, true);
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (std::none_of(nodes.begin(), nodes.end(), [&](Id v) { return moved[v] >= 0; })) return;
            for (Id v : nodes)
                if (v >= first_new) held[v] = false;
        });
    if (options.sweeps <= 0) return result;

    GridOptimizationOptions o;
    o.untangle.untangle_solver.method = untangle::Method::block_diagonal;
    o.untangle.optimize_solver.method = untangle::Method::block_diagonal;
    o.untangle.theta = options.theta;
    o.untangle.max_optimize_iterations = 1;  // one barrier pass of `sweeps` descent steps
    o.untangle.inner_steps = options.sweeps;
    o.untangle.max_untangle_iterations = 50;
    o.untangle.log = options.log;
    o.held = held;
    const std::vector<Vec3> projected = grid.points;
    const std::vector<double> before = scaled_jacobians(grid);
    const double floor = *std::min_element(before.begin(), before.end());
    result.solve = optimize_grid(grid, body, o).solve;
    keep_no_worse_than(grid, projected, floor, held, first_new);
    return result;
}

std::vector<BlockGrid> refine_family(const BlockGrid& coarse, const ImplicitFunction& body,
                                     int levels, const RefinementOptions& options) {
    if (levels < 1) throw std::invalid_argument("refine_family: levels must be at least 1");
    std::vector<BlockGrid> family = {coarse};
    for (int level = 2; level <= levels; ++level)
        family.push_back(refine_on_body(family.back(), body, options).grid);
    return family;
}

WallLayers refined_wall_layers(const WallLayers& law, int level) {
    WallLayers fine = law;
    for (int l = 1; l < level; ++l) {
        fine.growth_ratio = std::sqrt(fine.growth_ratio);
        fine.first_height /= 1 + fine.growth_ratio;
        fine.layers *= 2;
    }
    return fine;
}

FamilyLevel family_level(int level, const GridReport& report) {
    FamilyLevel f;
    f.level = level;
    f.cells = report.quality.cells;
    f.min_scaled_jacobian = report.quality.min_scaled_jacobian;
    f.mean_scaled_jacobian = report.quality.mean_scaled_jacobian;
    f.max_non_orthogonality = report.quality.max_non_orthogonality_deg;
    if (report.wall) {
        f.first_layer = report.wall->first_layer_mean;
        f.growth_ratio = report.wall->growth_ratio_mean;
    }
    return f;
}

std::string format_family_table(const std::vector<FamilyLevel>& levels) {
    std::string out =
        fmt::format("  {:>5} {:>12} {:>8} {:>8} {:>12} {:>8} {:>10}\n", "level", "cells", "min SJ",
                    "mean SJ", "first layer", "growth", "non-orth");
    for (const FamilyLevel& f : levels)
        out += fmt::format("  {:>5} {:>12} {:>8.4f} {:>8.4f} {:>12.4g} {:>8.4f} {:>10.2f}\n",
                           f.level, f.cells, f.min_scaled_jacobian, f.mean_scaled_jacobian,
                           f.first_layer, f.growth_ratio, f.max_non_orthogonality);
    return out;
}

std::string family_json(const std::vector<FamilyLevel>& levels) {
    std::string rows;
    for (const FamilyLevel& f : levels) {
        rows += fmt::format(
            "{}    {{\"level\": {}, \"directory\": \"level_{}\", \"cells\": {}, "
            "\"min_scaled_jacobian\": {}, \"mean_scaled_jacobian\": {}, "
            "\"first_layer_mean\": {}, \"growth_ratio_mean\": {}, "
            "\"max_non_orthogonality_deg\": {}}}",
            rows.empty() ? "" : ",\n", f.level, f.level, f.cells, f.min_scaled_jacobian,
            f.mean_scaled_jacobian, f.first_layer, f.growth_ratio, f.max_non_orthogonality);
    }
    return fmt::format("{{\n  \"refinement_ratio\": 2,\n  \"levels\": [\n{}\n  ]\n}}\n", rows);
}

}  // namespace hexmesh

#include "hexmesh/pipeline/refine.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/untangle_and_optimize.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"
#include "volume/refine.h"

namespace hexmesh {
namespace {

// A length scale for projection tolerances: the edge of a cube of the grid's mean cell volume,
// estimated from the bounding box (only its order of magnitude matters).
double cell_length_scale(const BlockGrid& grid) {
    const Box3 box = bounds_of(grid.points);
    const double cells = std::max<double>(1, double(grid.num_cells()));
    return box.diagonal() / std::cbrt(cells);
}

// The smaller of a and b, NaN if either is (std::min would drop a NaN in second place).
double lower(double a, double b) {
    return std::isnan(a) || std::isnan(b) ? std::numeric_limits<double>::quiet_NaN()
                                          : std::min(a, b);
}

// The smallest scaled Jacobian of `cells` (NaN if one is NaN).
double min_scaled_jacobian(const BlockGrid& grid, const std::vector<std::array<Id, 8>>& cells) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, cells.size(), 4096), std::numeric_limits<double>::infinity(),
        [&](const tbb::blocked_range<size_t>& r, double worst) {
            for (size_t c = r.begin(); c != r.end(); ++c) {
                std::array<Vec3, 8> p;
                for (int k = 0; k < 8; ++k) p[k] = grid.points[cells[c][k]];
                worst = lower(worst, hex_scaled_jacobian(p));
            }
            return worst;
        },
        lower);
}

// The smallest scaled Jacobian of the cells whose 8 nodes are all held.
double min_scaled_jacobian_held(const BlockGrid& grid, const std::vector<bool>& held) {
    double worst = std::numeric_limits<double>::infinity();
    for (const Block& block : grid.blocks) {
        const Dims d = block.cells();
        worst = lower(
            worst, tbb::parallel_reduce(
                       tbb::blocked_range<int>(0, d.nk), worst,
                       [&](const tbb::blocked_range<int>& r, double w) {
                           for (int k = r.begin(); k != r.end(); ++k)
                               for (int j = 0; j < d.nj; ++j)
                                   for (int i = 0; i < d.ni; ++i) {
                                       const std::array<Id, 8> nodes = cell_nodes(block, i, j, k);
                                       if (!std::all_of(nodes.begin(), nodes.end(),
                                                        [&](Id v) { return bool(held[v]); }))
                                           continue;
                                       std::array<Vec3, 8> p;
                                       for (int n = 0; n < 8; ++n) p[n] = grid.points[nodes[n]];
                                       w = lower(w, hex_scaled_jacobian(p));
                                   }
                           return w;
                       },
                       lower));
    }
    return worst;
}

// The functional's box targets can pull a cell below the quality interpolation gave it (at
// the irregular corners of the O-H core, where the coarse cell is no box). Where the polish
// leaves one of the optimized `cells` below the worst scaled Jacobian of the interpolated
// `grid` (one fine block), its free nodes go back to their interpolated (and projected)
// positions `saved` (free node ids `free` ascending, positions alike), until no cell is
// below it. The floor costs a pass over every cell of `grid`, so it is only computed when
// some optimized cell ends below `cells_floor`, their worst before the polish (the grid's
// worst is at most that).
// The other cells did not move; the projected grid itself meets the floor, so this ends.
// Skipped when interpolation left inverted cells (floor <= 0): then the polish is the
// untangling.
void keep_no_worse_than(BlockGrid& grid, const std::vector<std::array<Id, 8>>& cells,
                        double cells_floor, const std::vector<bool>& held,
                        const std::vector<Id>& free, const std::vector<Vec3>& saved) {
    if (!(cells_floor > 0) || min_scaled_jacobian(grid, cells) >= cells_floor) return;
    const double floor = std::min(cells_floor, min_scaled_jacobian_held(grid, held));
    if (!(floor > 0)) return;
    for (int round = 0; round < 100; ++round) {
        bool reverted = false;
        for (const std::array<Id, 8>& nodes : cells) {
            std::array<Vec3, 8> p;
            for (int k = 0; k < 8; ++k) p[k] = grid.points[nodes[k]];
            if (hex_scaled_jacobian(p) >= floor) continue;
            for (Id v : nodes) {
                if (held[v]) continue;
                const Vec3& back =
                    saved[size_t(std::lower_bound(free.begin(), free.end(), v) - free.begin())];
                if (grid.points[v] != back) {
                    grid.points[v] = back;
                    reverted = true;
                }
            }
        }
        if (!reverted) return;
    }
}

// Finishes one fine block whose new wall nodes are on the body: `sweeps` steps of the
// block-diagonal solver over the new nodes of the cells that touch a new wall node, but the
// nodes other blocks share (they keep the position their first block gave them, so blocks
// stay conforming whatever order they are finished in), then keep_no_worse_than. Returns
// how many nodes were free.
Id polish_block(RefinedBlock& piece, const ImplicitFunction& body,
                const RefinementOptions& options) {
    BlockGrid& grid = piece.grid;
    const Id count = static_cast<Id>(grid.points.size());
    std::vector<bool> unmoved(count), held(count, true);
    for (Id v = 0; v < count; ++v)
        unmoved[v] = piece.coarse[v] || (grid.kinds[v] != VertexKind::slip &&
                                         grid.kinds[v] != VertexKind::feature_edge);
    for (const std::array<Id, 8>& nodes : cells_not_held(grid, unmoved))
        for (Id v : nodes)
            if (!piece.coarse[v] && !piece.shared[v]) held[v] = false;
    std::vector<Id> free;
    std::vector<Vec3> saved;
    for (Id v = 0; v < count; ++v)
        if (!held[v]) {
            free.push_back(v);
            saved.push_back(grid.points[v]);
        }
    if (options.sweeps <= 0 || free.empty()) return 0;

    GridOptimizationOptions o;
    o.untangle.untangle_solver.method = untangle::Method::block_diagonal;
    o.untangle.optimize_solver.method = untangle::Method::block_diagonal;
    o.untangle.theta = options.theta;
    o.untangle.max_optimize_iterations = 1;  // one barrier pass of `sweeps` descent steps
    o.untangle.inner_steps = options.sweeps;
    o.untangle.max_untangle_iterations = 50;
    o.untangle.log = options.log;
    o.held = held;
    // Box targets even for an exterior grid's crease cells (keep_crease_shapes off): the
    // sweeps only move the new nodes next to the wall, and keep_no_worse_than below undoes
    // any that lower the worst cell.
    const std::vector<std::array<Id, 8>> cells = cells_not_held(grid, held);
    const double cells_floor = min_scaled_jacobian(grid, cells);
    optimize_grid(grid, body, o);
    keep_no_worse_than(grid, cells, cells_floor, held, free, saved);
    return static_cast<Id>(free.size());
}

}  // namespace

RefinementStats refine_blocks(const BlockGrid& coarse, const ImplicitFunction& body,
                              const RefinementOptions& options, const BlockSink& sink,
                              const std::vector<bool>* made) {
    RefinementStats stats;
    BlockRefiner refiner(coarse);
    // The fine grid's length scale: half the coarse one (8 times the cells in the same box).
    const double h = cell_length_scale(coarse) / 2;
    tbb::combinable<std::pair<Id, double>> moves([] { return std::pair<Id, double>{0, 0.0}; });
    const BlockRefiner::Place place = [&](const Vec3& x, VertexKind kind) {
        if (kind != VertexKind::slip && kind != VertexKind::feature_edge) return x;
        Vec3 p;
        if (kind == VertexKind::slip) {
            ProjectionOptions o;
            o.tolerance = 1e-12;
            p = project_to_surface(body, x, h, o).point;
        } else {
            p = project_to_crease(body, x, h);
        }
        auto& [n, longest] = moves.local();
        ++n;
        longest = std::max(longest, (p - x).norm());
        return p;
    };
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        if (made && !(*made)[b]) {
            refiner.skip(b, place);
            continue;
        }
        RefinedBlock piece = refiner.refine(b, place);
        stats.polished += polish_block(piece, body, options);
        sink(piece);
    }
    moves.combine_each([&](const std::pair<Id, double>& m) {
        stats.projected += m.first;
        stats.max_projection = std::max(stats.max_projection, m.second);
    });
    stats.points = refiner.num_points();
    return stats;
}

std::vector<BlockPiece> share_blocks(const BlockGrid& grid, int processes) {
    std::vector<BlockPiece> pieces;
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        const Block& block = grid.blocks[b];
        const Dims c = block.cells();
        const Dims fine{2 * c.ni, 2 * c.nj, 2 * c.nk};
        int axis = -1;
        for (int walls_allowed = 0; walls_allowed < 2 && axis < 0; ++walls_allowed)
            for (int d = 0; d < 3; ++d) {
                const bool walled = block.face_patch[size_t(2 * d)] == "wall" ||
                                    block.face_patch[size_t(2 * d + 1)] == "wall";
                if ((walls_allowed || !walled) && (axis < 0 || fine[d] > fine[axis])) axis = d;
            }
        pieces.push_back({b, axis, 0, fine[axis], 0, fine.count()});
    }
    // Halve the largest piece that has two coarse cells along its axis, until one per process;
    // at a coarse cell's side, so that each coarse cell is in one piece.
    while (int(pieces.size()) < processes) {
        auto largest = pieces.end();
        for (auto p = pieces.begin(); p != pieces.end(); ++p)
            if (p->hi - p->lo >= 4 && (largest == pieces.end() || p->cells > largest->cells))
                largest = p;
        if (largest == pieces.end()) break;
        BlockPiece upper = *largest;
        const Id per_layer = largest->cells / (largest->hi - largest->lo);
        largest->hi = upper.lo = largest->lo + 2 * ((largest->hi - largest->lo) / 4);
        largest->cells = per_layer * (largest->hi - largest->lo);
        upper.cells = per_layer * (upper.hi - upper.lo);
        pieces.insert(largest + 1, upper);
    }
    std::vector<size_t> order(pieces.size());
    for (size_t p = 0; p < order.size(); ++p) order[p] = p;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return pieces[a].cells > pieces[b].cells; });
    std::vector<Id> load(size_t(std::max(1, processes)), 0);
    for (const size_t p : order) {
        const auto least = std::min_element(load.begin(), load.end());
        pieces[p].process = int(least - load.begin());
        *least += pieces[p].cells;
    }
    return pieces;
}

RefinementResult refine_on_body(const BlockGrid& coarse, const ImplicitFunction& body,
                                const RefinementOptions& options) {
    RefinementResult result;
    BlockGrid& grid = result.grid;
    grid.points = coarse.points;
    grid.kinds = coarse.kinds;
    const RefinementStats stats = refine_blocks(coarse, body, options, [&](RefinedBlock& piece) {
        add_refined_block(grid, std::move(piece));
    });
    result.projected = stats.projected;
    result.max_projection = stats.max_projection;
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

void refine_levels(Job& job) {
    const int levels = job.settings.refinement.levels;
    if (levels == 1) return;
    refuse_invalid(job, job.reports[0], "level_1/");  // before refining it
    const RefinementOptions refinement;
    for (int level = 2; level <= levels; ++level) {
        RefinementResult r = refine_on_body(job.levels.back(), *job.body, refinement);
        job.timer.done(
            fmt::format("refinement level {}", level),
            fmt::format("({} cells, {} wall nodes projected)", r.grid.num_cells(), r.projected));
        job.levels.push_back(std::move(r.grid));
        job.reports.push_back(measure_level(job, level));
        job.timer.done(fmt::format("quality level {}", level));
    }
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

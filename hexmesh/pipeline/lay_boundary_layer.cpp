#include "hexmesh/pipeline/lay_boundary_layer.h"

#include <algorithm>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/quality/cell_quality.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// The nodes of the corner tets of `points` that are inverted and, with only_placed, have all
// four nodes placed (no solve could move them).
std::vector<bool> inverted_tet_nodes(const BlockGrid& grid, const std::vector<Vec3>& points,
                                     const std::vector<bool>& placed, bool only_placed) {
    std::vector<bool> hit(points.size(), false);
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (!std::any_of(nodes.begin(), nodes.end(), [&](Id v) { return placed[v]; })) return;
            std::array<Vec3, 8> p;
            for (int n = 0; n < 8; ++n) p[n] = points[nodes[n]];
            const std::array<double, 8> dets = corner_determinants(p);
            for (int c = 0; c < 8; ++c) {
                const auto& t = hex_corner_tets[c];
                if (dets[c] > 0 || (only_placed && !std::all_of(t.begin(), t.end(), [&](int n) {
                                        return placed[nodes[n]];
                                    })))
                    continue;
                for (int n : t) hit[nodes[n]] = true;
            }
        });
    return hit;
}

// Whether some corner tet of `grid` is inverted with none of its nodes `near` (true).
bool inverted_away_from(const BlockGrid& grid, const std::vector<bool>& near) {
    bool found = false;
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (found) return;
            std::array<Vec3, 8> p;
            for (int n = 0; n < 8; ++n) p[n] = grid.points[nodes[n]];
            const std::array<double, 8> dets = corner_determinants(p);
            for (int c = 0; c < 8 && !found; ++c) {
                const auto& t = hex_corner_tets[c];
                found = !(dets[c] > 0) &&
                        std::none_of(t.begin(), t.end(), [&](int n) { return near[nodes[n]]; });
            }
        });
    return found;
}

// Gives the wall lines with a `hit` node back to `joint`: all their nodes go back where
// `joint` had them, and none of them is placed any more. Returns the number of lines.
Id give_back_lines(BlockGrid& grid, const std::vector<Vec3>& joint, std::vector<bool>& placed,
                   const std::vector<bool>& hit) {
    Id given = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                if (!placed[f.node(p, q, 0)]) continue;  // not laid, or given back already
                bool line_hit = false;
                for (int t = 0; t < f.depth && !line_hit; ++t) line_hit = hit[f.node(p, q, t)];
                if (!line_hit) continue;
                for (int t = 0; t < f.depth; ++t) {
                    const Id v = f.node(p, q, t);
                    grid.points[v] = joint[v];
                    placed[v] = false;
                }
                ++given;
            }
    return given;
}

// Gives back to `joint` the wall lines whose laid cells cross: a line with a node in a corner
// tet that is inverted and has all four nodes placed, until no such tet is left (a line given
// back can leave its neighbour's cell blocked only through its own nodes, which are no longer
// placed). Returns the number of lines given back.
Id give_back_crossing_lines(BlockGrid& grid, const std::vector<Vec3>& joint,
                            std::vector<bool>& placed) {
    Id given = 0;
    for (Id more = 1; more > 0; given += more)
        more = give_back_lines(grid, joint, placed,
                               inverted_tet_nodes(grid, grid.points, placed, true));
    return given;
}

// The nodes the layer pass holds: all but the laid ones, the cells below relax_below and
// relax_rings rings of cells around both (none with relax_rings <= 0), and options.held.
std::vector<bool> relaxed_held(const BlockGrid& grid, const std::vector<bool>& placed,
                               const GridOptimizationOptions& options) {
    std::vector<bool> held = options.held;
    if (options.relax_rings > 0) {
        std::vector<bool> marked = placed;
        mark_cells_below(grid, scaled_jacobians(grid), options.relax_below, marked);
        held = grow_by_cells(grid, marked, options.relax_rings);
        held.flip();
        if (!options.held.empty())
            for (size_t v = 0; v < held.size(); ++v) held[v] = held[v] || options.held[v];
    }
    return held;
}

// The solver's budget of the layer pass: short, the rest of the grid is optimized already.
untangle::UntangleOptions short_budget(const untangle::UntangleOptions& given) {
    untangle::UntangleOptions o = given;
    o.max_untangle_iterations = std::min(o.max_untangle_iterations, 30);
    o.stall_iterations = std::min(o.stall_iterations, 10);
    return o;
}

}  // namespace

bool inverted_away_from_layers(const BlockGrid& grid, int layers) {
    return inverted_away_from(grid, wall_layer_nodes(grid, layers));
}

void lay_boundary_layer(BlockGrid& grid, const ImplicitFunction& body,
                        const GridOptimizationOptions& options, const std::vector<Vec3>& initial,
                        const std::vector<bool>& shaped, GridOptimizationResult& result) {
    const std::vector<Vec3> joint = grid.points;
    const std::vector<double> joint_sj = scaled_jacobians(grid);
    const double joint_min_sj =
        joint_sj.empty() ? 0 : *std::min_element(joint_sj.begin(), joint_sj.end());
    std::vector<Vec3> first_laid;  // a valid laid grid whose worst cell fell below half the joint's
    std::vector<bool> placed =
        extrude_wall_layers(grid, body, options.wall_layers, options.relax_rings);
    for (int attempt = 0; attempt < 2; ++attempt) {
        result.lines_given_back += give_back_crossing_lines(grid, joint, placed);
        result.laid_nodes = Id(std::count(placed.begin(), placed.end(), true));
        if (result.laid_nodes == 0) break;  // no line could be laid
        GridProblem g =
            corner_tet_problem(grid, initial, body, relaxed_held(grid, placed, options), shaped);
        untangle::Problem& problem = g.problem;
        for (Id i = 0; i < Id(problem.points.size()); ++i)
            if (placed[g.grid_id(i)]) problem.kinds[i] = VertexKind::fixed;
        hold_wall_quads(grid, initial, body, options.wall_fidelity, g);
        // A cell inverted between held nodes (beyond the relaxed rings) cannot be repaired.
        result.layers_blocked = Id(problem.blocked_elements().size());
        if (result.layers_blocked > 0) break;
        untangle::UntangleOptions budget = short_budget(options.untangle);
        // A work budget is the grid's (optimize_grid): each attempt gets what the joint pass
        // and the attempts before it left of it.
        if (options.untangle.max_work > 0)
            budget.max_work = std::max(options.untangle.max_work - result.untangling_work, 1.0);
        // Before the last attempt, the pass ends at its untangling's first stall when every
        // element still inverted has a laid node: the lines through them are then given back
        // and the rest laid again, which frees them in about a second, where the
        // continuation's restarts and last resorts spent up to 8 s on one or two elements
        // and freed none (the U outside, the hand inside: bench/RESULTS.md). Not when some
        // lies beyond the laid nodes: the spool outside, left so with 140 elements, lost its
        // layers and was refused.
        if (attempt == 0)
            budget.leave_to_next_pass = [&](const std::vector<Vec3>& x) {
                return g.inverted_all_touch(x, placed);
            };
        result.layers_held = untangle::untangle_and_optimize(problem, budget);
        result.layers_untangled |= result.layers_held.inverted_before > 0;
        result.untangling_work += result.layers_held.work;
        BlockGrid tried = grid;
        g.scatter(tried.points);
        std::vector<bool> hit;
        if (result.layers_held.inverted_after == 0) {
            const std::vector<double> sj = scaled_jacobians(tried);
            const double floor = 0.5 * joint_min_sj;
            if (attempt > 0 || !(*std::min_element(sj.begin(), sj.end()) < floor)) {
                grid.points = std::move(tried.points);
                result.layers_laid = true;
                return;
            }
            first_laid = tried.points;
            hit.assign(grid.points.size(), false);
            mark_cells_below(grid, sj, floor, hit);
        } else {
            hit = inverted_tet_nodes(grid, tried.points, placed, false);
        }
        result.lines_given_back += give_back_lines(grid, joint, placed, hit);
    }
    result.layers_laid = !first_laid.empty();
    // The first valid laid grid, else the joint result (the laid layers cross the rest).
    grid.points = result.layers_laid ? first_laid : joint;
}

}  // namespace hexmesh

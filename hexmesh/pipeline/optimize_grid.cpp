#include "hexmesh/pipeline/optimize_grid.h"

#include <algorithm>

#include "hexmesh/core/reference_hex.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"
#include "volume/wall_extrusion.h"

namespace hexmesh {
namespace {

// Mean length of the 4 edges of the cell along each of i, j, k.
Vec3 edge_lengths(const std::vector<Vec3>& points, const std::array<Id, 8>& nodes) {
    Vec3 sum = Vec3::Zero();
    for (const auto& e : hex_edges)
        sum[hex_edge_axis(e[0], e[1])] += (points[nodes[e[0]]] - points[nodes[e[1]]]).norm();
    return sum / 4;
}

// The corner tets of every cell that has a node free to move (`held` empty: every cell),
// with box targets of the cell's edge lengths in `target_points` (node positions of the grid).
untangle::Problem make_problem(const BlockGrid& grid, const std::vector<Vec3>& target_points,
                               const ImplicitFunction& body, const std::vector<bool>& held) {
    untangle::Problem p;
    p.points = grid.points;
    p.kinds = grid.kinds;
    for (size_t v = 0; v < held.size(); ++v)
        if (held[v]) p.kinds[v] = VertexKind::fixed;
    const Id cells = grid.num_cells();
    p.hexes.reserve(cells);
    p.hex_edges.reserve(cells);
    double total = 0;
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (!held.empty() && std::all_of(nodes.begin(), nodes.end(),
                                             [&](Id v) { return bool(held[v]); }))
                return;
            const Vec3 lengths = edge_lengths(target_points, nodes);
            total += lengths.sum();
            p.add_hex(nodes, lengths);
        });
    const double used = double(p.hexes.size());
    p.length_scale = used > 0 ? total / (3.0 * used) : 1.0;
    const double h = p.length_scale;
    p.surface_normal = [&body](Id, const Vec3& x) { return body.gradient(x); };
    p.project_to_surface = [&body, h](Id, const Vec3& x) {
        ProjectionOptions o;
        o.tolerance = 1e-12;
        return project_to_surface(body, x, h, o).point;
    };
    p.edge_tangent = [&body, h](Id, const Vec3& x) { return crease_tangent(body, x, 1e-3 * h); };
    p.project_to_edge = [&body, h](Id, const Vec3& x) { return project_to_crease(body, x, h); };
    return p;
}

}  // namespace

GridOptimizationResult optimize_grid(BlockGrid& grid, const ImplicitFunction& body,
                                     const GridOptimizationOptions& options) {
    GridOptimizationResult result;
    const std::vector<Vec3> initial = grid.points;  // the targets of both passes
    {
        untangle::Problem problem = make_problem(grid, initial, body, options.held);
        result.solve = untangle::untangle_and_optimize(problem, options.untangle);
        grid.points = problem.points;
    }
    if (options.wall_layers.layers > 0) {
        const std::vector<Vec3> joint = grid.points;
        const std::vector<bool> placed = extrude_wall_layers(grid, body, options.wall_layers);
        result.laid_nodes = Id(std::count(placed.begin(), placed.end(), true));
        if (result.laid_nodes == 0) return result;  // no line could be laid: nothing changed
        // Every cell stays in, those between laid nodes too: the result must be judged on all
        // of them. Laid layers that cross the grid are rarely repaired by the rest alone: a
        // short untangling budget, then the joint result is kept.
        untangle::Problem problem = make_problem(grid, initial, body, options.held);
        for (size_t v = 0; v < placed.size(); ++v)
            if (placed[v]) problem.kinds[v] = VertexKind::fixed;
        untangle::UntangleOptions short_budget = options.untangle;
        short_budget.max_untangle_iterations = std::min(short_budget.max_untangle_iterations, 30);
        short_budget.stall_iterations = std::min(short_budget.stall_iterations, 10);
        result.layers_held = untangle::untangle_and_optimize(problem, short_budget);
        result.layers_laid = result.layers_held.inverted_after == 0;
        if (result.layers_laid) grid.points = problem.points;
        else grid.points = joint;  // the laid layers cross the rest of the grid: keep the joint result
    }
    return result;
}

}  // namespace hexmesh

#include "hexmesh/pipeline/corner_tets.h"

#include <Eigen/LU>
#include <algorithm>
#include <memory>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/boundary_geometry.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// Mean length of the 4 edges of the cell along each of i, j, k. A cell flattened along an axis
// (its 4 edges there of no length, under 1e-9 of its longest: the nodes of a grid line laid on
// top of each other, such as where a continuation's path ends within the boundary layer beside
// a sharp tip) takes there the shortest of its other lengths: a target box of no volume would
// make the functional NaN, and the untangling would stop without a step.
Vec3 edge_lengths(const std::vector<Vec3>& points, const std::array<Id, 8>& nodes) {
    Vec3 sum = Vec3::Zero();
    for (const auto& e : hex_edges)
        sum[hex_edge_axis(e[0], e[1])] += (points[nodes[e[0]]] - points[nodes[e[1]]]).norm();
    Vec3 lengths = sum / 4;
    const double longest = lengths.maxCoeff();
    double shortest = longest;
    for (int a = 0; a < 3; ++a)
        if (lengths[a] > 1e-9 * longest) shortest = std::min(shortest, lengths[a]);
    for (int a = 0; a < 3; ++a)
        if (!(lengths[a] > 1e-9 * longest)) lengths[a] = shortest;
    return lengths;
}

// A cell shaped so is a target where each of its corners has a scaled Jacobian of at least
// this: a mitred crease cell is (0.4 and more), a cell a crease cuts across is not.
constexpr double shaped_target_min_sj = 0.2;

// The targets of a cell's 8 corner tets: its own corners in `target_points`; false (nothing
// added) when one of them has a scaled Jacobian under shaped_target_min_sj there.
bool add_shaped_hex(untangle::Problem& p, const std::vector<Vec3>& target_points,
                    const std::array<Id, 8>& nodes, const std::array<Id, 8>& ids) {
    std::array<untangle::TetTarget, 8> targets;
    for (int c = 0; c < 8; ++c) {
        const auto& t = hex_corner_tets[c];
        Mat3 h;
        for (int a = 0; a < 3; ++a)
            h.col(a) = target_points[nodes[t[a + 1]]] - target_points[nodes[t[0]]];
        const double det = h.determinant();
        if (!(det >= shaped_target_min_sj * h.col(0).norm() * h.col(1).norm() * h.col(2).norm()))
            return false;
        targets[c] = {h.inverse(), det / 6, 1};
    }
    for (int c = 0; c < 8; ++c) {
        const auto& t = hex_corner_tets[c];
        p.tets.push_back({ids[t[0]], ids[t[1]], ids[t[2]], ids[t[3]]});
        p.targets.push_back(targets[c]);
    }
    return true;
}

}  // namespace

bool GridProblem::inverted_all_touch(const std::vector<Vec3>& x,
                                     const std::vector<bool>& marked) const {
    for (Id e = 0; e < problem.num_elements(); ++e) {
        if (problem.det(x, e) > 0) continue;
        const auto element = problem.element(e);
        if (std::none_of(element.begin(), element.end(),
                         [&](Id v) { return bool(marked[grid_id(v)]); }))
            return false;
    }
    return true;
}

GridProblem corner_tet_problem(const BlockGrid& grid, const std::vector<Vec3>& target_points,
                               const ImplicitFunction& body, const std::vector<bool>& held,
                               const std::vector<bool>& shaped) {
    GridProblem g;
    untangle::Problem& p = g.problem;
    // The cells in the functional: all, or those with a node not held (listed once, so the
    // scans below do not visit the held part of a large grid).
    const std::vector<std::array<Id, 8>> listed =
        held.empty() ? std::vector<std::array<Id, 8>>{} : cells_not_held(grid, held);
    const auto each_cell = [&](auto&& f) {
        if (held.empty())
            for (const Block& block : grid.blocks)
                for_each_cell(block,
                              [&](int, int, int, const std::array<Id, 8>& nodes) { f(nodes); });
        else
            for (const std::array<Id, 8>& nodes : listed) f(nodes);
    };
    std::vector<Id> local;  // grid id -> problem id (-1: not in the problem); only with `held`
    if (held.empty()) {
        p.points = grid.points;
        p.kinds = grid.kinds;
    } else {
        local.assign(grid.points.size(), -1);
        for (const std::array<Id, 8>& nodes : listed)
            for (Id v : nodes)
                if (local[v] < 0) {
                    local[v] = Id(g.nodes.size());
                    g.nodes.push_back(v);
                }
        p.points.reserve(g.nodes.size());
        p.kinds.reserve(g.nodes.size());
        for (Id v : g.nodes) {
            p.points.push_back(grid.points[v]);
            p.kinds.push_back(held[v] ? VertexKind::fixed : grid.kinds[v]);
        }
    }
    const Id cells = held.empty() ? grid.num_cells() : Id(listed.size());
    p.hexes.reserve(cells);
    p.hex_edges.reserve(cells);
    double total = 0;
    each_cell([&](const std::array<Id, 8>& nodes) {
        const Vec3 lengths = edge_lengths(target_points, nodes);
        total += lengths.sum();
        std::array<Id, 8> ids = nodes;
        if (!local.empty())
            for (Id& v : ids) v = local[v];
        if (!shaped.empty() &&
            std::any_of(nodes.begin(), nodes.end(), [&](Id v) { return shaped[v]; }) &&
            add_shaped_hex(p, target_points, nodes, ids))
            return;
        p.add_hex(ids, lengths);
    });
    const double count = double(p.hexes.size() + p.tets.size() / 8);
    p.length_scale = count > 0 ? total / (3.0 * count) : 1.0;
    slide_on(body, p);
    return g;
}

void hold_wall_quads(const BlockGrid& grid, const std::vector<Vec3>& target_points,
                     const ImplicitFunction& body, double fidelity, GridProblem& g) {
    if (!(fidelity > 0)) return;
    untangle::Problem& p = g.problem;
    std::vector<Id> local;  // grid id -> problem id, -1 when not in the problem
    if (!g.nodes.empty()) {
        local.assign(grid.points.size(), -1);
        for (size_t i = 0; i < g.nodes.size(); ++i) local[g.nodes[i]] = Id(i);
    }
    const auto length = [&](Id a, Id b) { return (target_points[a] - target_points[b]).norm(); };
    for (const WallFace& f : wall_faces(grid)) {
        if (f.depth < 2) continue;
        for (int b = 0; b + 1 < f.nq; ++b)
            for (int a = 0; a + 1 < f.np; ++a) {
                const std::array<std::array<int, 2>, 4> corner{
                    {{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}}};
                untangle::HeldQuad q;
                bool in = true, free = false;
                double normal = 0;  // mean length of the cell's 4 edges off the wall
                for (int c = 0; c < 4 && in; ++c) {
                    const Id v = f.node(corner[c][0], corner[c][1], 0);
                    q.nodes[c] = local.empty() ? v : local[v];
                    in = q.nodes[c] >= 0;
                    free = free || (in && degrees_of_freedom(p.kinds[q.nodes[c]]) > 0);
                    normal += length(v, f.node(corner[c][0], corner[c][1], 1)) / 4;
                }
                if (!in || !free) continue;
                const auto edge = [&](int c, int d) {
                    return length(f.node(corner[c][0], corner[c][1], 0),
                                  f.node(corner[d][0], corner[d][1], 0));
                };
                const double area = (edge(0, 1) + edge(3, 2)) * (edge(0, 3) + edge(1, 2)) / 4;
                if (!(area > 0 && normal > 0)) continue;
                // (4/3) V / h^2 = (4/3) normal; with equal weights each corner tet weighs 1/6.
                q.weight = fidelity * 4 / 3 * normal;
                q.unit_weight = fidelity * 4 / 3 / area;
                p.held_quads.push_back(q);
            }
    }
    if (!p.held_quads.empty()) p.surface_value = [&body](const Vec3& x) { return body.value(x); };
}

void slide_on(const ImplicitFunction& body, untangle::Problem& p) {
    // Not owned: the caller keeps `body` alive as long as `p`.
    const std::shared_ptr<const ImplicitFunction> unowned(std::shared_ptr<const ImplicitFunction>{},
                                                          &body);
    BoundaryGeometry::implicit(unowned, p.length_scale).constrain(p);
}

std::vector<bool> crease_line_nodes(const BlockGrid& grid, const ImplicitFunction& body, int last) {
    std::vector<bool> marked(grid.points.size(), false);
    for (const WallFace& f : wall_faces(grid)) {
        const double side = grid_side(f, grid.points, body);
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                const Vec3 x0 = grid.points[f.node(p, q, 0)];
                const int pn = p + 1 < f.np ? p + 1 : p - 1;
                const double spacing = (grid.points[f.node(pn, q, 0)] - x0).norm();
                std::vector<Vec3> normals;
                append_wall_normals(body, x0, side, 1e-6 * spacing, normals);
                if (normals.size() < 2) continue;
                for (int t = 0; t <= std::min(last, f.depth - 1); ++t)
                    marked[f.node(p, q, t)] = true;
            }
    }
    return marked;
}

std::vector<bool> wall_layer_nodes(const BlockGrid& grid, int layers) {
    std::vector<bool> marked(grid.points.size(), false);
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p)
                for (int t = 0; t <= std::min(layers, f.depth - 1); ++t)
                    marked[f.node(p, q, t)] = true;
    return marked;
}

std::vector<bool> grow_by_cells(const BlockGrid& grid, std::vector<bool> marked, int rings) {
    for (int r = 0; r < rings; ++r) {
        std::vector<bool> next = marked, unmarked = marked;
        unmarked.flip();
        for (const std::array<Id, 8>& nodes : cells_not_held(grid, unmarked))
            for (Id v : nodes) next[v] = true;
        marked = std::move(next);
    }
    return marked;
}

void mark_cells_below(const BlockGrid& grid, const std::vector<double>& sj, double threshold,
                      std::vector<bool>& marked) {
    size_t c = 0;
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (!(sj[c++] >= threshold))
                for (Id v : nodes) marked[v] = true;
        });
}

}  // namespace hexmesh

#include "hexmesh/pipeline/optimize_grid.h"

#include <Eigen/LU>
#include <algorithm>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/boundary_geometry.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// Mean length of the 4 edges of the cell along each of i, j, k.
Vec3 edge_lengths(const std::vector<Vec3>& points, const std::array<Id, 8>& nodes) {
    Vec3 sum = Vec3::Zero();
    for (const auto& e : hex_edges)
        sum[hex_edge_axis(e[0], e[1])] += (points[nodes[e[0]]] - points[nodes[e[1]]]).norm();
    return sum / 4;
}

// The functional over the cells that have a node free to move (`held` empty: every cell):
// its points are the grid nodes `nodes` (local -> grid id; empty: all grid nodes, same ids),
// the nodes of those cells only, so a refined grid whose new wall nodes alone are free
// costs memory for them, not for the whole grid.
struct GridProblem {
    untangle::Problem problem;
    std::vector<Id> nodes;
    Id grid_id(Id local) const { return nodes.empty() ? local : nodes[local]; }
    // The solved positions back into the grid.
    void scatter(std::vector<Vec3>& points) const {
        if (nodes.empty())
            points = problem.points;
        else
            for (size_t i = 0; i < nodes.size(); ++i) points[nodes[i]] = problem.points[i];
    }
};

// Nodes 0 .. last of the wall-normal lines that start on a crease or corner of the body (two
// or more distinct faces active at the wall node, within 1e-6 of the wall spacing there).
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

// Box targets of the cell's edge lengths in `target_points` (node positions of the grid); the
// cells with a `shaped` node (empty: none) target their own shapes there.
GridProblem make_problem(const BlockGrid& grid, const std::vector<Vec3>& target_points,
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

// `marked` grown by `rings` rings of cells: every node of a cell with a marked node is marked,
// `rings` times over.
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

// Marks every node of the cells whose scaled Jacobian (`sj`, in for_each_cell order over the
// blocks) is not at least `threshold`.
void mark_cells_below(const BlockGrid& grid, const std::vector<double>& sj, double threshold,
                      std::vector<bool>& marked) {
    size_t c = 0;
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            if (!(sj[c++] >= threshold))
                for (Id v : nodes) marked[v] = true;
        });
}

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

}  // namespace

void slide_on(const ImplicitFunction& body, untangle::Problem& p) {
    // Not owned: the caller keeps `body` alive as long as `p`.
    const std::shared_ptr<const ImplicitFunction> unowned(std::shared_ptr<const ImplicitFunction>{},
                                                          &body);
    BoundaryGeometry::implicit(unowned, p.length_scale).constrain(p);
}

GridOptimizationResult optimize_grid(BlockGrid& grid, const ImplicitFunction& body,
                                     const GridOptimizationOptions& options) {
    GridOptimizationResult result;
    // The targets of both passes: the grid as given (kept aside only when a second pass needs it).
    const std::vector<Vec3> initial =
        options.wall_layers.layers > 0 ? grid.points : std::vector<Vec3>{};
    // The nodes whose cells keep their shapes in both passes: the crease lines' nodes up to
    // layers + 1 (the laid layers' cells and the two beyond), found once on the grid as given.
    const std::vector<bool> shaped =
        options.keep_crease_shapes ? crease_line_nodes(grid, body, options.wall_layers.layers + 1)
                                   : std::vector<bool>{};
    {
        GridProblem g = make_problem(grid, grid.points, body, options.held, shaped);
        untangle::UntangleOptions joint = options.untangle;
        if (options.wall_layers.layers > 0) {
            // Inverted elements all at the wall or its layers are left to the pass below,
            // which lays the layers again and frees them in seconds where the continuation's
            // restarts and last resorts took minutes (the tripod outside: 1 element, 110 s).
            joint.leave_to_next_pass = [&g,
                                        near = wall_layer_nodes(grid, options.wall_layers.layers)](
                                           const std::vector<Vec3>& x) {
                const untangle::Problem& p = g.problem;
                for (Id e = 0; e < p.num_elements(); ++e) {
                    if (p.det(x, e) > 0) continue;
                    const auto nodes = p.element(e);
                    if (std::none_of(nodes.begin(), nodes.end(),
                                     [&](Id v) { return bool(near[g.grid_id(v)]); }))
                        return false;
                }
                return true;
            };
        }
        result.solve = untangle::untangle_and_optimize(g.problem, joint);
        g.scatter(grid.points);
    }
    // Laying the layers again moves the wall's layer nodes and optimizes the cells around them
    // and around the poor ones: it can free inverted elements the joint pass left at the wall
    // (the tripod outside). On every run measured it freed none that the joint pass left away
    // from the wall and its layers, and took up to minutes there (bench/RESULTS.md): skipped.
    result.layers_skipped =
        options.wall_layers.layers > 0 && result.solve.inverted_after > 0 &&
        inverted_away_from(grid, wall_layer_nodes(grid, options.wall_layers.layers));
    if (options.wall_layers.layers > 0 && !result.layers_skipped) {
        const std::vector<Vec3> joint = grid.points;
        const std::vector<double> joint_sj = scaled_jacobians(grid);
        const double joint_min_sj =
            joint_sj.empty() ? 0 : *std::min_element(joint_sj.begin(), joint_sj.end());
        std::vector<Vec3>
            first_laid;  // a valid laid grid whose worst cell fell below half the joint's
        std::vector<bool> placed =
            extrude_wall_layers(grid, body, options.wall_layers, options.relax_rings);
        // The layers, the cells below relax_below (scaled Jacobian, once the layers are
        // laid), and the cells up to `relax_rings` rings around both are optimized again; the
        // rest of the grid (already optimized by the joint pass, and unmoved) is held. With
        // relax_rings <= 0 the whole grid is. Lines whose laid cells cross are given back to
        // the joint result first; when the pass still leaves inverted cells, or cells under half
        // the joint result's worst scaled Jacobian, the lines through them are given back too
        // and it runs once more; then the better valid result is kept, else the joint one.
        for (int attempt = 0; attempt < 2; ++attempt) {
            result.lines_given_back += give_back_crossing_lines(grid, joint, placed);
            result.laid_nodes = Id(std::count(placed.begin(), placed.end(), true));
            if (result.laid_nodes == 0) break;  // no line could be laid
            std::vector<bool> held = options.held;
            if (options.relax_rings > 0) {
                std::vector<bool> marked = placed;
                mark_cells_below(grid, scaled_jacobians(grid), options.relax_below, marked);
                held = grow_by_cells(grid, marked, options.relax_rings);
                held.flip();
                if (!options.held.empty())
                    for (size_t v = 0; v < held.size(); ++v) held[v] = held[v] || options.held[v];
            }
            GridProblem g = make_problem(grid, initial, body, held, shaped);
            untangle::Problem& problem = g.problem;
            for (Id i = 0; i < Id(problem.points.size()); ++i)
                if (placed[g.grid_id(i)]) problem.kinds[i] = VertexKind::fixed;
            // A cell inverted between held nodes (beyond the relaxed rings) cannot be repaired.
            result.layers_blocked = Id(problem.blocked_elements().size());
            if (result.layers_blocked > 0) break;
            untangle::UntangleOptions short_budget = options.untangle;
            short_budget.max_untangle_iterations =
                std::min(short_budget.max_untangle_iterations, 30);
            short_budget.stall_iterations = std::min(short_budget.stall_iterations, 10);
            result.layers_held = untangle::untangle_and_optimize(problem, short_budget);
            BlockGrid tried = grid;
            g.scatter(tried.points);
            std::vector<bool> hit;
            if (result.layers_held.inverted_after == 0) {
                const std::vector<double> sj = scaled_jacobians(tried);
                const double floor = 0.5 * joint_min_sj;
                if (attempt > 0 || !(*std::min_element(sj.begin(), sj.end()) < floor)) {
                    grid.points = std::move(tried.points);
                    result.layers_laid = true;
                    return result;
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
    return result;
}

namespace {

// How a grid ranks in the polish: fewer cells a solver refuses (inverted, or failing
// checkMesh's cell checks), then a higher worst scaled Jacobian, then fewer cells under the
// polish threshold (the worst cell may be one the polish holds).
struct PolishRank {
    Id refused = 0;
    double min_sj = 0;
    Id below = 0;
    // `sj`: the grid's scaled Jacobians (scaled_jacobians).
    PolishRank(const BlockGrid& grid, const std::vector<double>& sj, double threshold) {
        const QualityReport q = measure_quality(grid);
        refused =
            q.inverted_cells + q.negative_pyramids + q.faces_over_90_deg + q.nonpositive_volumes;
        min_sj = q.min_scaled_jacobian;
        below =
            Id(std::count_if(sj.begin(), sj.end(), [&](double v) { return !(v >= threshold); }));
    }
    bool better_than(const PolishRank& o) const {
        if (refused != o.refused) return refused < o.refused;
        if (min_sj != o.min_sj) return min_sj > o.min_sj;
        return below < o.below;
    }
};

}  // namespace

std::vector<bool> wall_layer_nodes(const BlockGrid& grid, int layers) {
    std::vector<bool> marked(grid.points.size(), false);
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p)
                for (int t = 0; t <= std::min(layers, f.depth - 1); ++t)
                    marked[f.node(p, q, t)] = true;
    return marked;
}

PolishResult polish_worst_cells(BlockGrid& grid, const ImplicitFunction& body,
                                const PolishOptions& options) {
    PolishResult result;
    std::vector<double> sj = scaled_jacobians(grid);
    const PolishRank first(grid, sj, options.below);
    result.min_sj_before = result.min_sj_after = first.min_sj;
    result.refused_before = result.refused_after = first.refused;
    // The cells to polish, in for_each_cell order over the blocks (`sj` of the grid as it is).
    const auto to_polish = [&] {
        std::vector<bool> cells(size_t(grid.num_cells()), false);
        if (options.refused_only) {
            for (Id c : find_refused_cells(to_hex_mesh(grid))) cells[c] = true;
        } else {
            for (size_t c = 0; c < sj.size(); ++c) cells[c] = !(sj[c] >= options.below);
        }
        return cells;
    };
    std::vector<bool> cells = to_polish();
    result.cells = result.cells_after = Id(std::count(cells.begin(), cells.end(), true));
    std::vector<Vec3> best = grid.points;
    PolishRank best_rank = first;
    for (int round = 0; round < options.rounds && std::count(cells.begin(), cells.end(), true) > 0;
         ++round) {
        std::vector<bool> marked(grid.points.size(), false);
        size_t c = 0;
        for (const Block& block : grid.blocks)
            for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
                if (cells[c++])
                    for (Id v : nodes) marked[v] = true;
            });
        std::vector<bool> held = grow_by_cells(grid, marked, options.rings);
        held.flip();
        if (!options.held.empty())
            for (size_t v = 0; v < held.size(); ++v) held[v] = held[v] || options.held[v];
        GridProblem g = make_problem(grid, grid.points, body, held, {});
        if (g.nodes.empty()) break;  // every node of those cells held (the wall and its layers)
        const untangle::UntangleResult r =
            untangle::untangle_and_optimize(g.problem, options.untangle);
        ++result.rounds;
        result.seconds += r.seconds;
        if (r.inverted_after > 0) break;  // the next round would start from worse
        g.scatter(grid.points);  // the next round starts here, even if this one ranks lower
        sj = scaled_jacobians(grid);
        cells = to_polish();
        const PolishRank rank(grid, sj, options.below);
        if (rank.better_than(best_rank)) {
            best = grid.points, best_rank = rank;
            result.cells_after = Id(std::count(cells.begin(), cells.end(), true));
        }
    }
    grid.points = std::move(best);
    result.min_sj_after = best_rank.min_sj;
    result.refused_after = best_rank.refused;
    return result;
}

}  // namespace hexmesh

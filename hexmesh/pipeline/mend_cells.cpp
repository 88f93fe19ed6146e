#include "hexmesh/pipeline/mend_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"

namespace hexmesh {
namespace {

// The cells of each node (CSR: cells[offset[v] .. offset[v + 1])) and the cell across each
// face (face_neighbours).
struct Adjacency {
    std::vector<Id> offset, cells, across;
    Adjacency(const HexMesh& mesh)
        : offset(mesh.points.size() + 1, 0), across(face_neighbours(mesh)) {
        for (Id v : mesh.hexes) ++offset[v + 1];
        for (size_t v = 0; v < mesh.points.size(); ++v) offset[v + 1] += offset[v];
        cells.resize(mesh.hexes.size());
        std::vector<Id> next(offset.begin(), offset.end() - 1);
        for (size_t i = 0; i < mesh.hexes.size(); ++i) cells[next[mesh.hexes[i]]++] = Id(i / 8);
    }
    std::pair<const Id*, const Id*> of(Id v) const {
        return {&cells[offset[v]], &cells[offset[v + 1]]};
    }
};

// The cells around a node as a move is judged: how many cells have an inverted corner tet
// (exact orientation) and how many such tets, then how many cells the solver refuses (margin
// <= 0), then how many of their faces it refuses (skewness over max_solver_skewness; each face
// once, also between two of these cells), then the smallest margin, a refused face's being
// (max - skewness) / max. A move may not trade a valid cell for fewer refused ones, nor a
// refused cell for an accepted one that falls, nor a skewed face for a refused cell.
struct Score {
    int inverted = 0, inverted_tets = 0, refused = 0, skewed = 0;
    double lowest = std::numeric_limits<double>::infinity();
    bool better_than(const Score& s) const {
        if (inverted != s.inverted) return inverted < s.inverted;
        if (inverted_tets != s.inverted_tets) return inverted_tets < s.inverted_tets;
        if (refused != s.refused) return refused < s.refused;
        if (skewed != s.skewed) return skewed < s.skewed;
        return lowest > s.lowest + 1e-12;
    }
};

// With by_jacobian, `lowest` is the smallest scaled Jacobian of the cells instead (a skewed face
// still counts, before it).
Score score_at(const HexMesh& mesh, const Adjacency& around, Id v, bool by_jacobian = false) {
    Score s;
    const auto [first, end] = around.of(v);
    // The centres of the cells around v, each computed once: a face between two of them
    // needs both.
    std::vector<Vec3> centres;
    for (const Id* c = first; c != end; ++c) centres.push_back(hex_centre(mesh.corners(*c)));
    for (const Id* c = first; c != end; ++c) {
        const std::array<Vec3, 8> p = mesh.corners(*c);
        const double m = solver_margin(p);
        const int inverted = count_inverted_corner_tets(p);
        s.inverted += inverted > 0;
        s.inverted_tets += inverted;
        s.refused += !(m > 0);
        s.lowest = std::min(s.lowest, by_jacobian ? hex_scaled_jacobian(p) : m);
        const Vec3& centre = centres[size_t(c - first)];
        for (int f = 0; f < 6; ++f) {
            const Id n = around.across[6 * *c + f];
            const Id* beside = std::find(first, end, n);
            if (beside != end && n < *c) continue;  // a face between two of them: counted once
            const Vec3 other = n < 0           ? Vec3::Zero()
                               : beside != end ? centres[size_t(beside - first)]
                                               : hex_centre(mesh.corners(n));
            const double skew = hex_face_skewness(p, f, centre, n >= 0 ? &other : nullptr);
            if (skew > max_solver_skewness) {
                ++s.skewed;
                if (!by_jacobian)
                    s.lowest =
                        std::min(s.lowest, (max_solver_skewness - skew) / max_solver_skewness);
            }
        }
    }
    return s;
}

double mean_edge_at(const HexMesh& mesh, const Adjacency& around, Id v) {
    double sum = 0;
    int count = 0;
    for (auto [c, end] = around.of(v); c != end; ++c)
        for (const auto& e : hex_edges) {
            const Id a = mesh.hexes[8 * *c + e[0]], b = mesh.hexes[8 * *c + e[1]];
            if (a == v || b == v) sum += (mesh.points[a] - mesh.points[b]).norm(), ++count;
        }
    return count ? sum / count : 0;
}

// The lowest margin (Score::lowest) over `nodes`.
double lowest(const HexMesh& mesh, const Adjacency& around, const std::vector<Id>& nodes) {
    double m = std::numeric_limits<double>::infinity();
    for (Id v : nodes) m = std::min(m, score_at(mesh, around, v).lowest);
    return m;
}

// The trial positions of a node at `x` for a step of `step` (appended to `out`).
using TrialMoves = std::function<void(Id v, const Vec3& x, double step, std::vector<Vec3>& out)>;

struct RoundResult {
    Id moves = 0;         // nodes moved
    bool trying = false;  // some node still had a step worth trying
};

const std::array<Vec3, 6> axis_directions = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                                             -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};

// The smallest scaled Jacobian of the cells around v.
double worst_jacobian_at(const HexMesh& mesh, const Adjacency& around, Id v) {
    double low = std::numeric_limits<double>::infinity();
    for (auto [c, end] = around.of(v); c != end; ++c)
        low = std::min(low, hex_scaled_jacobian(mesh.corners(*c)));
    return low;
}

// The move of `tried` that the node v takes, or `start`. By the solver's checks (score_at), the
// best if better than at `start`. By the scaled Jacobian (by_jacobian), the trials that raise the
// worst of the node's cells over `low` (its value at `start`) ranked on it alone, and the first
// whose Score (by_jacobian) is better than at `start`: at most one full score per move kept.
Vec3 best_move(HexMesh& mesh, const Adjacency& around, Id v, const Vec3& start,
               const std::vector<Vec3>& tried, bool by_jacobian, double low) {
    Vec3 best = start;
    if (!by_jacobian) {
        Score best_score = score_at(mesh, around, v);
        for (const Vec3& x : tried) {
            mesh.points[v] = x;
            const Score m = score_at(mesh, around, v);
            if (m.better_than(best_score)) best = x, best_score = m;
        }
    } else {
        std::vector<std::pair<double, size_t>> ranked;
        for (size_t t = 0; t < tried.size(); ++t) {
            mesh.points[v] = tried[t];
            const double w = worst_jacobian_at(mesh, around, v);
            if (w > low + 1e-12) ranked.emplace_back(-w, t);
        }
        std::sort(ranked.begin(), ranked.end());
        if (!ranked.empty()) {
            mesh.points[v] = start;
            const Score before = score_at(mesh, around, v, true);
            for (const auto& [w, t] : ranked) {
                mesh.points[v] = tried[t];
                if (score_at(mesh, around, v, true).better_than(before)) {
                    best = tried[t];
                    break;
                }
            }
        }
    }
    mesh.points[v] = best;
    return best;
}

// One round over `nodes`: each movable node whose margin (or, by_jacobian, worst scaled
// Jacobian around it) is not yet `enough` tries the moves `trials` gives for a step of step[i]
// and takes the best (best_move); a node that finds none halves its step, down to last_step
// edges.
RoundResult node_round(HexMesh& mesh, const Adjacency& around, const std::vector<Id>& nodes,
                       const std::function<bool(Id)>& movable, const TrialMoves& trials,
                       bool by_jacobian, double enough, double last_step,
                       std::vector<double>& step) {
    RoundResult r;
    std::vector<Vec3> tried;
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Id v = nodes[i];
        if (!movable(v) || step[i] <= 0) continue;
        const double low =
            by_jacobian ? worst_jacobian_at(mesh, around, v) : score_at(mesh, around, v).lowest;
        if (low > enough) continue;
        const double edge = mean_edge_at(mesh, around, v);
        if (step[i] < last_step * edge) continue;
        r.trying = true;
        const Vec3 start = mesh.points[v];
        tried.clear();
        trials(v, start, step[i], tried);
        if (best_move(mesh, around, v, start, tried, by_jacobian, low) != start)
            ++r.moves;
        else
            step[i] *= 0.5;
    }
    return r;
}

}  // namespace

MendResult mend_refused_cells(BlockGrid& grid, const ImplicitFunction& body, const MendOptions& o) {
    MendResult result;
    HexMesh mesh = to_hex_mesh(grid);
    std::vector<Id> refused = find_refused_cells(mesh);
    result.refused_before = result.refused_after = Id(refused.size());
    if (refused.empty()) return result;
    const Adjacency around(mesh);
    const auto movable = [&](Id v) {
        const VertexKind k = grid.kinds[v];
        return (k == VertexKind::interior || k == VertexKind::slip) &&
               (o.held.empty() || !o.held[v]);
    };
    // The nodes of the refused cells, then of the cells sharing a node with those.
    std::vector<Id> cells = refused, nodes;
    const auto nodes_of_cells = [&] {
        nodes.clear();
        for (Id c : cells)
            for (int i = 0; i < 8; ++i) nodes.push_back(mesh.hexes[8 * c + i]);
        std::sort(nodes.begin(), nodes.end());
        nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    };
    nodes_of_cells();
    result.min_margin_before = lowest(mesh, around, nodes);
    for (int ring = 0; ring < o.rings && !refused.empty(); ++ring) {
        if (ring > 0) {
            std::vector<Id> wider;
            for (Id v : nodes)
                for (auto [c, end] = around.of(v); c != end; ++c) wider.push_back(*c);
            std::sort(wider.begin(), wider.end());
            wider.erase(std::unique(wider.begin(), wider.end()), wider.end());
            cells = std::move(wider);
            nodes_of_cells();
        }
        std::vector<double> step(nodes.size());
        for (size_t i = 0; i < nodes.size(); ++i)
            step[i] = o.first_step * mean_edge_at(mesh, around, nodes[i]);
        // Six moves along the axes, a slip node's projected back onto u = 0.
        const TrialMoves axes = [&](Id v, const Vec3& x, double h, std::vector<Vec3>& out) {
            for (const Vec3& d : axis_directions) {
                const Vec3 y = x + h * d;
                out.push_back(grid.kinds[v] == VertexKind::slip
                                  ? project_to_surface(body, y, mean_edge_at(mesh, around, v)).point
                                  : y);
            }
        };
        for (int round = 0; round < o.rounds; ++round) {
            const RoundResult r =
                node_round(mesh, around, nodes, movable, axes, false, o.enough, o.last_step, step);
            result.moves += r.moves;
            if (!r.trying) break;
            if (r.moves == 0 && round > 0 && lowest(mesh, around, nodes) > 0) break;
        }
        refused = find_refused_cells(mesh);
    }
    result.min_margin_after = lowest(mesh, around, nodes);
    result.refused_after = Id(refused.size());
    grid.points = std::move(mesh.points);
    return result;
}

namespace {

// `x` moved along the level set of `body` through it by `offset` (tangent to it), and back onto
// the level u = level by steps along grad u; `x` itself where that does not land within
// 1e-6 |offset| of the level (a vanishing gradient: a point of the medial axis).
Vec3 along_level(const ImplicitFunction& body, const Vec3& x, const Vec3& offset, double level) {
    const double length = offset.norm();
    Vec3 y = x + offset;
    for (int i = 0; i < 8; ++i) {
        const double r = body.value(y) - level;
        if (!std::isfinite(r)) return x;
        if (std::abs(r) <= 1e-9 * length) return y;
        const Vec3 g = body.gradient(y);
        const double g2 = g.squaredNorm();
        if (!(g2 > 1e-2)) return x;  // |grad u| is about 1 near u = 0
        y -= (r / g2) * g;
    }
    return std::abs(body.value(y) - level) <= 1e-6 * length ? y : x;
}

}  // namespace

LiftResult lift_worst_cells(BlockGrid& grid, const ImplicitFunction& body, const LiftOptions& o) {
    LiftResult result;
    HexMesh mesh = to_hex_mesh(grid);
    std::vector<double> sj = scaled_jacobians(mesh);
    const auto count_below = [&] {
        return Id(std::count_if(sj.begin(), sj.end(), [&](double v) { return !(v >= o.below); }));
    };
    result.cells_before = result.cells_after = count_below();
    result.min_sj_before = result.min_sj_after =
        sj.empty() ? 0 : *std::min_element(sj.begin(), sj.end());
    if (result.cells_before == 0) return result;
    const Adjacency around(mesh);
    // The nodes of the cells under `below` (`sj` is in to_hex_mesh's cell order, the blocks'
    // for_each_cell order), and `rings` rings of cells around them.
    std::vector<bool> marked(mesh.points.size(), false);
    mark_cells_below(grid, sj, o.below, marked);
    marked = grow_by_cells(grid, std::move(marked), o.rings);
    std::vector<Id> nodes;
    for (size_t v = 0; v < marked.size(); ++v)
        if (marked[v]) nodes.push_back(Id(v));
    const auto movable = [&](Id v) {
        const VertexKind k = grid.kinds[v];
        return (k == VertexKind::interior || k == VertexKind::slip ||
                k == VertexKind::feature_edge) &&
               (o.held.empty() || !o.held[v]);
    };
    // The level of u each node keeps: 0 for the wall's slip nodes, its own for o.on_level.
    std::vector<double> level(nodes.size(), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Id v = nodes[i];
        if (grid.kinds[v] == VertexKind::slip)
            level[i] = 0;
        else if (!o.on_level.empty() && o.on_level[v])
            level[i] = body.value(mesh.points[v]);
    }
    std::vector<double> step(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i)
        step[i] = o.first_step * mean_edge_at(mesh, around, nodes[i]);
    // Along its crease (two directions), along its level set (four tangent directions) or along
    // the axes.
    const TrialMoves moves = [&](Id v, const Vec3& x, double h, std::vector<Vec3>& out) {
        const size_t i = size_t(std::lower_bound(nodes.begin(), nodes.end(), v) - nodes.begin());
        if (grid.kinds[v] == VertexKind::feature_edge) {
            const double edge = mean_edge_at(mesh, around, v);
            const Vec3 t = crease_tangent(body, x, 1e-3 * edge);
            if (t.squaredNorm() > 0)
                for (const Vec3& d : {t, Vec3(-t)})
                    out.push_back(project_to_crease(body, x + h * d, edge));
            return;
        }
        if (std::isnan(level[i])) {
            for (const Vec3& d : axis_directions) out.push_back(x + h * d);
            return;
        }
        const TangentFrame t = tangent_frame(body, x);
        for (const Vec3& d : {t.t1, Vec3(-t.t1), t.t2, Vec3(-t.t2)})
            out.push_back(along_level(body, x, h * d, level[i]));
    };
    // The lines with a marked node whose nodes all move (the wall's slip or on its crease, the
    // layers' on their levels), each with its nodes' levels and step.
    struct Line {
        std::vector<Id> nodes;
        std::vector<double> levels;
        double step = 0;
    };
    std::vector<Line> lines;
    for (const std::vector<Id>& l : o.lines) {
        if (l.size() < 2 || grid.kinds[l[0]] != VertexKind::slip ||
            std::none_of(l.begin(), l.end(), [&](Id v) { return bool(marked[v]); }) ||
            !std::all_of(l.begin(), l.end(), movable) ||
            !std::all_of(l.begin() + 1, l.end(), [&](Id v) {
                return grid.kinds[v] == VertexKind::interior && !o.on_level.empty() &&
                       o.on_level[v];
            }))
            continue;
        Line line{l, {0}, o.first_step * mean_edge_at(mesh, around, l[0])};
        for (size_t t = 1; t < l.size(); ++t) line.levels.push_back(body.value(mesh.points[l[t]]));
        lines.push_back(std::move(line));
    }
    const auto worst_on = [&](const Line& l) {
        double w = std::numeric_limits<double>::infinity();
        for (Id v : l.nodes) w = std::min(w, worst_jacobian_at(mesh, around, v));
        return w;
    };
    const auto score_on = [&](const Line& l) {
        Score s;
        for (Id v : l.nodes) {
            const Score n = score_at(mesh, around, v, true);
            s.inverted += n.inverted, s.inverted_tets += n.inverted_tets;
            s.refused += n.refused, s.skewed += n.skewed, s.lowest = std::min(s.lowest, n.lowest);
        }
        return s;
    };
    // A line moved whole (every node by the same offset along its level) or sheared (node t of T
    // by t / T of it, the wall node staying), along the wall's tangent directions: the lines
    // that leave the wall leaning, which a node moved alone cannot straighten.
    const auto line_round = [&] {
        RoundResult r;
        std::vector<Vec3> start, x;
        for (Line& l : lines) {
            const double low = worst_on(l);
            if (low > o.below || l.step < o.last_step * mean_edge_at(mesh, around, l.nodes[0]))
                continue;
            r.trying = true;
            start.clear();
            for (Id v : l.nodes) start.push_back(mesh.points[v]);
            const TangentFrame f = tangent_frame(body, start[0]);
            const size_t T = l.nodes.size() - 1;
            std::vector<std::pair<double, std::vector<Vec3>>> ranked;
            for (const Vec3& d : {f.t1, Vec3(-f.t1), f.t2, Vec3(-f.t2)})
                for (int shear = 0; shear < 2; ++shear) {
                    x.clear();
                    for (size_t t = 0; t <= T; ++t) {
                        const double share = shear ? double(t) / double(T) : 1.0;
                        x.push_back(share == 0 ? start[t]
                                               : along_level(body, start[t], share * l.step * d,
                                                             l.levels[t]));
                        mesh.points[l.nodes[t]] = x.back();
                    }
                    const double w = worst_on(l);
                    if (w > low + 1e-12) ranked.emplace_back(-w, x);
                }
            for (size_t t = 0; t <= T; ++t) mesh.points[l.nodes[t]] = start[t];
            std::sort(ranked.begin(), ranked.end(),
                      [](const auto& a, const auto& b) { return a.first < b.first; });
            bool moved = false;
            if (!ranked.empty()) {
                const Score before = score_on(l);
                for (const auto& [w, xs] : ranked) {
                    for (size_t t = 0; t <= T; ++t) mesh.points[l.nodes[t]] = xs[t];
                    if (score_on(l).better_than(before)) {
                        moved = true;
                        break;
                    }
                }
                if (!moved)
                    for (size_t t = 0; t <= T; ++t) mesh.points[l.nodes[t]] = start[t];
            }
            if (moved)
                ++r.moves;
            else
                l.step *= 0.5;
        }
        return r;
    };
    for (int round = 0; round < o.rounds; ++round) {
        const RoundResult r =
            node_round(mesh, around, nodes, movable, moves, true, o.below, o.last_step, step);
        const RoundResult l = line_round();
        result.moves += r.moves + l.moves;
        result.line_moves += l.moves;
        if (!r.trying && !l.trying) break;
    }
    sj = scaled_jacobians(mesh);
    result.cells_after = count_below();
    result.min_sj_after = sj.empty() ? 0 : *std::min_element(sj.begin(), sj.end());
    grid.points = std::move(mesh.points);
    return result;
}

}  // namespace hexmesh

#include "hexmesh/pipeline/mend_cells.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

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

// score_at (by the scaled Jacobian) summed over `nodes`: a cell counts once per node of the
// list it holds; `lowest` the smallest.
Score score_of(const HexMesh& mesh, const Adjacency& around, const std::vector<Id>& nodes) {
    Score s;
    for (Id v : nodes) {
        const Score n = score_at(mesh, around, v, true);
        s.inverted += n.inverted, s.inverted_tets += n.inverted_tets;
        s.refused += n.refused, s.skewed += n.skewed, s.lowest = std::min(s.lowest, n.lowest);
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

// The frames of the cells around v (hex_frame_jacobians, 9 a cell), into `out`.
void frames_at(const HexMesh& mesh, const Adjacency& around, Id v, std::vector<double>& out) {
    out.clear();
    for (auto [c, end] = around.of(v); c != end; ++c) {
        const std::array<double, 9> f = hex_frame_jacobians(mesh.corners(*c));
        out.insert(out.end(), f.begin(), f.end());
    }
}

// The point of the convex hull of `points` nearest the origin (Wolfe's algorithm: a corral of
// points whose affine hull's nearest point lies inside their hull, grown by the point farthest
// back along the current nearest point until none lies back by more than 1e-10 of the longest's
// squared length). Zero when the hull holds the origin, or when the point found fails to be
// one every point lies ahead along (each p . x >= x . x / 2: rounding).
Eigen::VectorXd nearest_in_hull(const std::vector<Eigen::VectorXd>& points) {
    const Eigen::Index dim = points.front().size();
    double scale = 0;
    size_t shortest = 0;
    for (size_t k = 0; k < points.size(); ++k) {
        scale = std::max(scale, points[k].squaredNorm());
        if (points[k].squaredNorm() < points[shortest].squaredNorm()) shortest = k;
    }
    std::vector<size_t> corral{shortest};
    std::vector<double> w{1.0};
    // The corral's Gram matrix, kept in step with it: each dot product computed once.
    Eigen::MatrixXd gram(1, 1);
    gram(0, 0) = points[shortest].dot(points[shortest]);
    Eigen::VectorXd x = points[shortest];
    for (int major = 0; major < 500 && x.squaredNorm() > 1e-20 * scale; ++major) {
        size_t back = 0;
        for (size_t k = 1; k < points.size(); ++k)
            if (points[k].dot(x) < points[back].dot(x)) back = k;
        if (x.squaredNorm() - points[back].dot(x) <= 1e-10 * scale ||
            std::find(corral.begin(), corral.end(), back) != corral.end())
            break;
        corral.push_back(back);
        w.push_back(0);
        const Eigen::Index last = gram.rows();
        gram.conservativeResize(last + 1, last + 1);
        for (Eigen::Index i = 0; i <= last; ++i)
            gram(i, last) = gram(last, i) = points[corral[size_t(i)]].dot(points[back]);
        for (int minor = 0; minor < 500; ++minor) {
            // The affine hull's nearest point: weights v, sum 1, from the Gram matrix's KKT system.
            const Eigen::Index k = Eigen::Index(corral.size());
            Eigen::MatrixXd a = Eigen::MatrixXd::Zero(k + 1, k + 1);
            a.topLeftCorner(k, k) = gram;
            for (Eigen::Index i = 0; i < k; ++i) a(i, k) = a(k, i) = 1;
            Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k + 1);
            rhs(k) = 1;
            const Eigen::VectorXd v = a.completeOrthogonalDecomposition().solve(rhs).head(k);
            if (v.minCoeff() > 1e-12) {
                w.assign(v.data(), v.data() + k);
                break;
            }
            // Towards it until a weight reaches zero; that point leaves the corral.
            double theta = 1;
            for (Eigen::Index i = 0; i < k; ++i)
                if (v(i) <= 1e-12 && w[size_t(i)] - v(i) > 0)
                    theta = std::min(theta, w[size_t(i)] / (w[size_t(i)] - v(i)));
            std::vector<size_t> kept;
            std::vector<Eigen::Index> kept_at;
            std::vector<double> kept_w;
            for (Eigen::Index i = 0; i < k; ++i) {
                const double wi = (1 - theta) * w[size_t(i)] + theta * v(i);
                if (wi > 1e-12)
                    kept.push_back(corral[size_t(i)]), kept_at.push_back(i), kept_w.push_back(wi);
            }
            if (kept.empty()) break;
            corral = std::move(kept);
            w = std::move(kept_w);
            gram = Eigen::MatrixXd(gram(kept_at, kept_at));
        }
        x = Eigen::VectorXd::Zero(dim);
        for (size_t i = 0; i < corral.size(); ++i) x += w[i] * points[corral[i]];
        // The point just taken in left again at once (rounding): it would come back each time.
        if (std::find(corral.begin(), corral.end(), back) == corral.end()) break;
    }
    for (const Eigen::VectorXd& p : points)
        if (!(p.dot(x) >= 0.5 * x.squaredNorm())) return Eigen::VectorXd::Zero(dim);
    return x;
}

// Offsets, in the span of `basis` (1 to 3 orthonormal vectors), along which the smallest of
// `frames` rises fastest to first order, for nodes that `move(offset)` places (offset zero:
// back where they were): the max-min steepest ascent (Freitag and Plassmann's optimization of
// the worst element round a node), the point nearest the origin of the convex hull of the
// gradients of the frames within 0.01 of the smallest (forward differences of 1e-4 `edge`).
// Along it the smallest rises at |d|^2 until another frame, falling or rising more slowly,
// meets it: that reach (at most `cap`), and its half, are appended to `out`. None when the
// hull holds the origin (a frame the move cannot raise is the smallest, or the gradients
// balance).
void ascent_offsets(const std::function<void(const Vec3&)>& move,
                    const std::function<void(std::vector<double>&)>& frames,
                    const std::vector<Vec3>& basis, double edge, double cap,
                    std::vector<Vec3>& out) {
    std::vector<double> f0, f;
    frames(f0);
    if (f0.empty()) return;
    const double h = 1e-4 * edge;
    std::vector<Vec3> grad(f0.size(), Vec3::Zero());
    for (size_t j = 0; j < basis.size(); ++j) {
        move(h * basis[j]);
        frames(f);
        for (size_t k = 0; k < f0.size(); ++k) grad[k][int(j)] = (f[k] - f0[k]) / h;
    }
    move(Vec3::Zero());
    const double low = *std::min_element(f0.begin(), f0.end());
    if (!(low < 1)) return;
    std::vector<Vec3> active;
    for (size_t k = 0; k < f0.size(); ++k)
        if (f0[k] <= low + 0.01 && grad[k].allFinite()) active.push_back(grad[k]);
    if (active.empty()) return;
    std::vector<Eigen::VectorXd> hull;
    for (const Vec3& g : active) hull.push_back(g.head(Eigen::Index(basis.size())));
    const Eigen::VectorXd near = nearest_in_hull(hull);
    Vec3 d = Vec3::Zero();
    d.head(near.size()) = near;
    const double rate = d.squaredNorm();
    if (!(rate > 1e-12)) return;
    double reach = cap / d.norm();
    for (size_t k = 0; k < f0.size(); ++k)
        if (f0[k] < 1e29 && f0[k] > low + 0.01 && grad[k].dot(d) < rate)
            reach = std::min(reach, (f0[k] - low) / (rate - grad[k].dot(d)));
    Vec3 offset = Vec3::Zero();
    for (size_t j = 0; j < basis.size(); ++j) offset += d[int(j)] * basis[j];
    for (const double share : {1.0, 0.5}) out.push_back(share * reach * offset);
}

// ascent_offsets for node v alone.
void node_ascent(HexMesh& mesh, const Adjacency& around, Id v, const std::vector<Vec3>& basis,
                 double edge, double cap, std::vector<Vec3>& out) {
    const Vec3 x = mesh.points[v];
    ascent_offsets([&](const Vec3& offset) { mesh.points[v] = x + offset; },
                   [&](std::vector<double>& f) { frames_at(mesh, around, v, f); }, basis, edge, cap,
                   out);
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
// and takes the best (best_move), or else those `then` gives (if any); a node that finds none
// halves its step, down to last_step edges.
RoundResult node_round(HexMesh& mesh, const Adjacency& around, const std::vector<Id>& nodes,
                       const std::function<bool(Id)>& movable, const TrialMoves& trials,
                       bool by_jacobian, double enough, double last_step, std::vector<double>& step,
                       const TrialMoves& then = {}) {
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
        bool moved = best_move(mesh, around, v, start, tried, by_jacobian, low) != start;
        if (!moved && then) {
            tried.clear();
            then(v, start, step[i], tried);
            moved = !tried.empty() &&
                    best_move(mesh, around, v, start, tried, by_jacobian, low) != start;
        }
        if (moved)
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

// How a node may move in the joint ascent: its basis (axes, its level's tangents, its
// crease's tangent, or none) and where an offset takes it (back onto its level or crease).
struct NodeFreedom {
    std::vector<Vec3> basis;
    std::function<Vec3(const Vec3& x, const Vec3& offset)> place;
};

// The worst cells raised jointly, step by step: the frames (hex_frame_jacobians) within 0.01
// of the grid's smallest, in the cells (at most 128) that hold them; their gradients in the
// moves of all those cells' nodes at once (forward differences of 1e-4 edges, each node moved
// as `freedom` places it, back onto its level or crease: a difference along the tangent alone
// misses how the projection moves it, and the step it predicts lowers the worst cell; none
// along a direction where that placing kinks); with them
// the gradients of the solver margins' terms (solver_margins) within 0.01 of what a solver
// refuses and of the faces' distances to the skewness it refuses within 1 % of it, in the cells
// around those nodes; the point of the convex hull of all these gradients nearest
// the origin (the max-min steepest ascent of the nodes together: along it every such frame and
// margin rises, where each node alone may already be at a max-min point of its own cells); and a
// step along it from 0.1 of the shortest edge at the moving nodes, halved until the cells around
// them all come out above the smallest with a Score no worse (no more cells inverted, refused or
// with skewed faces, summed over the moving nodes as score_at counts them). It raises the worst
// cells whether or not they are under the lift's `below`. Stops when more than 128 cells are
// that near the smallest (spread over the grid: left to the functional), when none of their
// nodes may move, when the hull holds the origin, when no step helps, each of these with the
// frames within 0.01 of the smallest and again within 0.001 and 1e-4 (a frame 0.005 above it
// need not rise, and its gradient may balance the others'), all of that again with fewer of the
// nodes' directions (those where the node's place is smooth to 0.01 of an offset, not 0.1);
// when ten steps raised the smallest by less than 0.001 together, or after `iterations`.
// Returns the steps taken.
Id joint_ascent(HexMesh& mesh, const Adjacency& around,
                const std::function<NodeFreedom(Id)>& freedom, int iterations) {
    Id taken = 0;
    std::vector<double> sj = scaled_jacobians(mesh);
    std::vector<double> lows;  // the smallest before each step
    for (int it = 0; it < iterations; ++it) {
        const double low = *std::min_element(sj.begin(), sj.end());
        // Ten steps that raised it by less than 0.001 together: it crawls.
        if (lows.size() >= 10 && low - lows[lows.size() - 10] < 1e-3) break;
        lows.push_back(low);
        // One step with the frames within `band` of the smallest; whether it was taken.
        const auto step = [&](double band, double smooth) {
            std::vector<Id> cells;
            for (Id c = 0; c < Id(sj.size()); ++c)
                if (sj[c] <= low + band) cells.push_back(c);
            if (cells.size() > 128) return false;  // spread over the grid: left to the functional
            // The variables: each moving node's basis coordinates.
            std::vector<Id> nodes;
            for (Id c : cells)
                for (int a = 0; a < 8; ++a) nodes.push_back(mesh.hexes[8 * c + a]);
            std::sort(nodes.begin(), nodes.end());
            nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
            const double h = 1e-4 * mean_edge_at(mesh, around, mesh.hexes[8 * cells[0]]);
            std::vector<NodeFreedom> free(nodes.size());
            // Each node's place at an offset of +h along each direction of its basis kept.
            std::vector<std::vector<Vec3>> placed(nodes.size());
            std::vector<int> first(nodes.size() + 1, 0);
            for (size_t i = 0; i < nodes.size(); ++i) {
                free[i] = freedom(nodes[i]);
                // A direction along which an offset of +-h does not move the node by it to within
                // `smooth` h has no derivative there: its level kinks (a distance field's trilinear
                // cells, a face's edge) or its projection does not land on one side (where the
                // gradient nearly vanishes, between a hand's fingers). A difference across it
                // predicts a rise the step does not give, and the ascent stops: the node does not
                // move along it.
                const Vec3 x = mesh.points[nodes[i]];
                std::vector<Vec3> basis;
                for (const Vec3& e : free[i].basis) {
                    const Vec3 ahead = free[i].place(x, h * e), back = free[i].place(x, -h * e);
                    if ((ahead - x - h * e).norm() <= smooth * h &&
                        (back - x + h * e).norm() <= smooth * h) {
                        basis.push_back(e);
                        placed[i].push_back(ahead);
                    }
                }
                free[i].basis = std::move(basis);
                first[i + 1] = first[i] + int(free[i].basis.size());
            }
            const int n = first.back();
            if (n == 0) return false;
            // Forward differences of the quantities measure(cell c) listed in `which`, in the
            // unknowns of the nodes `of` (each once) that are in `nodes`: one gradient of n
            // unknowns per quantity.
            const auto differences = [&](Id c, const auto& measure, const std::vector<int>& which,
                                         const std::vector<Id>& of) {
                const auto m0 = measure(c);
                std::vector<Eigen::VectorXd> g(which.size(), Eigen::VectorXd::Zero(n));
                for (const Id v : of) {
                    const auto at = std::lower_bound(nodes.begin(), nodes.end(), v);
                    if (at == nodes.end() || *at != v) continue;
                    const size_t i = size_t(at - nodes.begin());
                    const Vec3 x = mesh.points[v];
                    for (size_t j = 0; j < free[i].basis.size(); ++j) {
                        mesh.points[v] = placed[i][j];
                        const auto ahead = measure(c);
                        for (size_t q = 0; q < which.size(); ++q)
                            g[q][first[i] + int(j)] = (ahead[which[q]] - m0[which[q]]) / h;
                    }
                    mesh.points[v] = x;
                }
                return g;
            };
            const auto corners_of = [&](Id c) {
                return std::vector<Id>(mesh.hexes.begin() + 8 * c, mesh.hexes.begin() + 8 * c + 8);
            };
            const auto frames = [&](Id c) { return hex_frame_jacobians(mesh.corners(c)); };
            std::vector<Eigen::VectorXd> grads;
            for (Id c : cells) {
                const std::array<double, 9> f0 = frames(c);
                std::vector<int> act;
                for (int k = 0; k < 9; ++k)
                    if (f0[k] <= low + band) act.push_back(k);
                for (auto& v : differences(c, frames, act, corners_of(c)))
                    if (v.allFinite()) grads.push_back(std::move(v));
            }
            std::vector<Id> touched;
            for (Id v : nodes)
                for (auto [c, end] = around.of(v); c != end; ++c) touched.push_back(*c);
            std::sort(touched.begin(), touched.end());
            touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
            // Cells within 0.01 of what a solver refuses (solver_margin) must not come nearer: the
            // gradients of their margin's terms that are (solver_margins: the smallest of them
            // kinks where two meet, and a difference across it raises one while the step lowers the
            // other) join the hull, so the step raises them too.
            const auto margins = [&](Id c) { return solver_margins(mesh.corners(c)); };
            for (Id c : touched) {
                const std::array<double, 14> m0 = margins(c);
                std::vector<int> act;
                for (int k = 0; k < 14; ++k)
                    if (m0[k] <= 0.01) act.push_back(k);
                if (act.empty()) continue;
                for (auto& g : differences(c, margins, act, corners_of(c)))
                    if (g.allFinite() && g.squaredNorm() > 0) grads.push_back(std::move(g));
            }
            // Faces within 1 % of the skewness a solver refuses (max_solver_skewness) must not
            // reach it: the gradients of their distances to it (relative), in the moves of the
            // nodes of both cells (the skewness weighs the two centres), join the hull too.
            const auto skew_room = [&](Id c, int f) {
                const Id beside = around.across[6 * c + f];
                const std::array<Vec3, 8> p = mesh.corners(c);
                const Vec3 other = beside >= 0 ? hex_centre(mesh.corners(beside)) : Vec3::Zero();
                const double skew =
                    hex_face_skewness(p, f, hex_centre(p), beside >= 0 ? &other : nullptr);
                return std::array<double, 1>{(max_solver_skewness - skew) / max_solver_skewness};
            };
            for (Id c : touched)
                for (int f = 0; f < 6; ++f) {
                    const Id beside = around.across[6 * c + f];
                    // A face between two touched cells: once, from the lower.
                    if (beside >= 0 && beside < c &&
                        std::binary_search(touched.begin(), touched.end(), beside))
                        continue;
                    const auto room = [&](Id cell) { return skew_room(cell, f); };
                    if (!(room(c)[0] <= 0.01)) continue;
                    std::vector<Id> of = corners_of(c);
                    if (beside >= 0)
                        for (const Id v : corners_of(beside))
                            if (std::find(of.begin(), of.end(), v) == of.end()) of.push_back(v);
                    Eigen::VectorXd g = std::move(differences(c, room, {0}, of).front());
                    if (g.allFinite() && g.squaredNorm() > 0) grads.push_back(std::move(g));
                }
            if (grads.empty()) return false;
            const Eigen::VectorXd d = nearest_in_hull(grads);
            if (!(d.squaredNorm() > 1e-12)) return false;
            // The moved nodes' offsets per unit step, and the cells they touch.
            std::vector<Vec3> offset(nodes.size(), Vec3::Zero());
            double longest = 0, edge = std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < nodes.size(); ++i) {
                for (size_t j = 0; j < free[i].basis.size(); ++j)
                    offset[i] += d[first[i] + int(j)] * free[i].basis[j];
                longest = std::max(longest, offset[i].norm());
                if (offset[i].norm() > 0)
                    edge = std::min(edge, mean_edge_at(mesh, around, nodes[i]));
            }
            if (!(longest > 0)) return false;
            const Score before = score_of(mesh, around, nodes);
            std::vector<Vec3> start(nodes.size());
            for (size_t i = 0; i < nodes.size(); ++i) start[i] = mesh.points[nodes[i]];
            bool moved = false;
            for (double t = 0.1 * edge / longest; t > 1e-4 * edge / longest && !moved; t *= 0.5) {
                for (size_t i = 0; i < nodes.size(); ++i)
                    if (offset[i].squaredNorm() > 0)
                        mesh.points[nodes[i]] = free[i].place(start[i], t * offset[i]);
                double worst = std::numeric_limits<double>::infinity();
                for (Id c : touched) worst = std::min(worst, hex_scaled_jacobian(mesh.corners(c)));
                const Score after = score_of(mesh, around, nodes);
                moved = worst > low + 1e-9 && after.inverted <= before.inverted &&
                        after.inverted_tets <= before.inverted_tets &&
                        after.refused <= before.refused && after.skewed <= before.skewed;
                if (!moved)
                    for (size_t i = 0; i < nodes.size(); ++i) mesh.points[nodes[i]] = start[i];
            }
            if (!moved) return false;
            ++taken;
            for (Id c : touched) sj[c] = hex_scaled_jacobian(mesh.corners(c));
            return true;
        };
        // Where the frames within 0.01 of the smallest balance (the hull holds the origin) or
        // no step helps, those within 0.001, then 1e-4: the ones that need not rise with it.
        // Where none helps, the same with the directions whose place departs from the offset
        // by more than 0.01 h left out, not 0.1 h: in a first layer a node a tenth of h off its
        // level can lower a cell more than the step raises it (the bull outside stopped at
        // 0.192 with every step size lowering the smallest by about 1e-5).
        bool moved = false;
        for (const double smooth : {0.1, 0.01}) {
            for (const double band : {1e-2, 1e-3, 1e-4})
                if ((moved = step(band, smooth))) break;
            if (moved) break;
        }
        if (!moved) break;
    }
    return taken;
}

std::optional<Sphere> far_field_sphere(const BlockGrid& grid, std::vector<bool>& on_far) {
    on_far.assign(grid.points.size(), false);
    std::vector<Id> far;
    for (const Block& b : grid.blocks)
        for (int f = 0; f < 6; ++f) {
            if (b.face_patch[f] != "farfield") continue;
            const WallFace face = block_face(b, BlockFace(f));
            for (int q = 0; q < face.nq; ++q)
                for (int p = 0; p < face.np; ++p) {
                    const Id v = face.node(p, q, 0);
                    if (!on_far[v]) far.push_back(v);
                    on_far[v] = true;
                }
        }
    if (far.size() < 4) {
        on_far.clear();
        return std::nullopt;
    }
    // |x - c|^2 = R^2: 2 (x - m) . (c - m) + R^2 - |c - m|^2 = |x - m|^2, linear in c and
    // R^2 - |c - m|^2 (m the nodes' mean, for the digits).
    Vec3 m = Vec3::Zero();
    for (Id v : far) m += grid.points[v];
    m /= double(far.size());
    Eigen::MatrixX4d a(far.size(), 4);
    Eigen::VectorXd b(far.size());
    for (size_t i = 0; i < far.size(); ++i) {
        const Vec3 x = grid.points[far[i]] - m;
        a.row(Eigen::Index(i)) << 2 * x.x(), 2 * x.y(), 2 * x.z(), 1.0;
        b[Eigen::Index(i)] = x.squaredNorm();
    }
    const Eigen::Vector4d s = a.colPivHouseholderQr().solve(b);
    const Vec3 centre = m + s.head<3>();
    const double r2 = s[3] + s.head<3>().squaredNorm();
    bool on_one = r2 > 0;
    for (size_t i = 0; i < far.size() && on_one; ++i)
        on_one =
            std::abs((grid.points[far[i]] - centre).norm() - std::sqrt(r2)) <= 1e-9 * std::sqrt(r2);
    if (!on_one) {
        on_far.clear();
        return std::nullopt;
    }
    return Sphere(centre, std::sqrt(r2));
}

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
    const auto on_far = [&](Id v) { return o.far && !o.on_far.empty() && o.on_far[v]; };
    const auto movable = [&](Id v) {
        const VertexKind k = grid.kinds[v];
        return (k == VertexKind::interior || k == VertexKind::slip ||
                k == VertexKind::feature_edge || on_far(v)) &&
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
    // The level set a node slides on (the far field's, or its level of u) and its level;
    // nullptr for a node free along the axes (or on a crease).
    const auto sliding = [&](Id v) -> std::pair<const ImplicitFunction*, double> {
        if (on_far(v)) return {o.far, 0.0};
        if (grid.kinds[v] == VertexKind::slip) return {&body, 0.0};
        if (grid.kinds[v] != VertexKind::interior || o.on_level.empty() || !o.on_level[v])
            return {nullptr, 0.0};
        // A node the sweeps did not list keeps the level it is on.
        const size_t i = size_t(std::lower_bound(nodes.begin(), nodes.end(), v) - nodes.begin());
        return {&body, i < nodes.size() && nodes[i] == v ? level[i] : body.value(mesh.points[v])};
    };
    std::vector<double> step(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i)
        step[i] = o.first_step * mean_edge_at(mesh, around, nodes[i]);
    // Along its crease (two directions), along its level set (four tangent directions) or along
    // the axes.
    const TrialMoves moves = [&](Id v, const Vec3& x, double h, std::vector<Vec3>& out) {
        if (grid.kinds[v] == VertexKind::feature_edge) {
            const double edge = mean_edge_at(mesh, around, v);
            const Vec3 t = crease_tangent(body, x, 1e-3 * edge);
            if (t.squaredNorm() > 0)
                for (const Vec3& d : {t, Vec3(-t)})
                    out.push_back(project_to_crease(body, x + h * d, edge));
            return;
        }
        const auto [on, l] = sliding(v);
        if (!on) {
            for (const Vec3& d : axis_directions) out.push_back(x + h * d);
            return;
        }
        const TangentFrame t = tangent_frame(*on, x);
        for (const Vec3& d : {t.t1, Vec3(-t.t1), t.t2, Vec3(-t.t2)})
            out.push_back(along_level(*on, x, h * d, l));
    };
    // When none of those raises the node's worst cell: the max-min ascent (not on a crease).
    const TrialMoves ascent = [&](Id v, const Vec3& x, double h, std::vector<Vec3>& out) {
        if (grid.kinds[v] == VertexKind::feature_edge) return;
        const double edge = mean_edge_at(mesh, around, v);
        std::vector<Vec3> offsets;
        const auto [on, l] = sliding(v);
        if (!on) {
            node_ascent(mesh, around, v, {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}, edge, h,
                        offsets);
            for (const Vec3& d : offsets) out.push_back(x + d);
            return;
        }
        const TangentFrame t = tangent_frame(*on, x);
        node_ascent(mesh, around, v, {t.t1, t.t2}, edge, h, offsets);
        for (const Vec3& d : offsets) out.push_back(along_level(*on, x, d, l));
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
            // When none of those raises it: the max-min ascent of the frames of the line's
            // cells, whole and sheared.
            for (int shear = 0; o.ascent && ranked.empty() && shear < 2; ++shear) {
                const auto share = [&](size_t t) { return shear ? double(t) / double(T) : 1.0; };
                std::vector<Vec3> offsets;
                std::vector<double> part;
                ascent_offsets(
                    [&](const Vec3& o) {
                        for (size_t t = 0; t <= T; ++t)
                            mesh.points[l.nodes[t]] = start[t] + share(t) * o;
                    },
                    [&](std::vector<double>& f) {
                        f.clear();
                        for (Id v : l.nodes) {
                            frames_at(mesh, around, v, part);
                            f.insert(f.end(), part.begin(), part.end());
                        }
                    },
                    {f.t1, f.t2}, mean_edge_at(mesh, around, l.nodes[0]), l.step, offsets);
                for (const Vec3& o : offsets) {
                    x.clear();
                    for (size_t t = 0; t <= T; ++t) {
                        x.push_back(share(t) == 0
                                        ? start[t]
                                        : along_level(body, start[t], share(t) * o, l.levels[t]));
                        mesh.points[l.nodes[t]] = x.back();
                    }
                    const double w = worst_on(l);
                    if (w > low + 1e-12) ranked.emplace_back(-w, x);
                }
            }
            for (size_t t = 0; t <= T; ++t) mesh.points[l.nodes[t]] = start[t];
            std::sort(ranked.begin(), ranked.end(),
                      [](const auto& a, const auto& b) { return a.first < b.first; });
            bool moved = false;
            if (!ranked.empty()) {
                const Score before = score_of(mesh, around, l.nodes);
                for (const auto& [w, xs] : ranked) {
                    for (size_t t = 0; t <= T; ++t) mesh.points[l.nodes[t]] = xs[t];
                    if (score_of(mesh, around, l.nodes).better_than(before)) {
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
        const RoundResult r = node_round(mesh, around, nodes, movable, moves, true, o.below,
                                         o.last_step, step, o.ascent ? ascent : TrialMoves());
        const RoundResult l = line_round();
        result.moves += r.moves + l.moves;
        result.line_moves += l.moves;
        if (!r.trying && !l.trying) break;
    }
    if (o.ascent) {
        const auto freedom = [&](Id v) {
            NodeFreedom f;
            if (!movable(v)) return f;
            const double edge = mean_edge_at(mesh, around, v);
            const auto [on, l] = sliding(v);
            if (grid.kinds[v] == VertexKind::feature_edge) {
                const Vec3 t = crease_tangent(body, mesh.points[v], 1e-3 * edge);
                if (t.squaredNorm() > 0) f.basis = {t};
                f.place = [&body, edge](const Vec3& x, const Vec3& d) {
                    return project_to_crease(body, x + d, edge);
                };
            } else if (on) {
                const TangentFrame t = tangent_frame(*on, mesh.points[v]);
                f.basis = {t.t1, t.t2};
                f.place = [on = on, l = l](const Vec3& x, const Vec3& d) {
                    return along_level(*on, x, d, l);
                };
            } else {
                f.basis = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
                f.place = [](const Vec3& x, const Vec3& d) { return Vec3(x + d); };
            }
            return f;
        };
        result.joint_steps = joint_ascent(mesh, around, freedom, o.joint_iterations);
    }
    sj = scaled_jacobians(mesh);
    result.cells_after = count_below();
    result.min_sj_after = sj.empty() ? 0 : *std::min_element(sj.begin(), sj.end());
    grid.points = std::move(mesh.points);
    return result;
}

namespace {

// A wall line as restore_layer_heights sees it (its wall node does not move there): its
// nodes from the wall out, the unit normals of the body's pieces at its wall node (into the
// grid; one on a smooth wall), how many of the law's layers it takes, and at a crease or corner
// the step that is 1 above every piece (unit_offset).
struct LayerLine {
    std::vector<Id> nodes;
    std::vector<Vec3> normals;
    int layers = 0;
    std::optional<Vec3> crease_step;
    // The last node it moves: its layers' and as many beyond, short of its far end.
    int last() const { return std::min(2 * layers, int(nodes.size()) - 2); }
    // Node y's heights above the pieces, each off dm by at most `tolerance`.
    bool on(const Vec3& x0, const Vec3& y, double dm, double tolerance) const {
        return std::all_of(normals.begin(), normals.end(), [&](const Vec3& n) {
            return std::abs((y - x0).dot(n) - dm) <= tolerance;
        });
    }
};

// The lines of the grid's wall faces that lay some of the law's layers (each once: a line
// shared by two blocks' faces is the same nodes), but none through a node another line runs
// through too (crossed_lines, as extrude_wall_layers leaves them: a single block walled on
// several sides).
std::vector<LayerLine> layer_lines(const BlockGrid& grid, const ImplicitFunction& body,
                                   const WallLayers& law) {
    const std::vector<Vec3>& x = grid.points;
    const std::vector<WallFace> faces = wall_faces(grid);
    const std::vector<bool> crossed = crossed_lines(grid, faces);
    std::vector<LayerLine> lines;
    std::vector<char> seen(x.size(), 0);
    for (const WallFace& f : faces) {
        const double side = grid_side(f, x, body);
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                const Id w = f.node(p, q, 0);
                if (seen[w]) continue;
                seen[w] = 1;
                LayerLine line;
                for (int t = 0; t < f.depth; ++t) line.nodes.push_back(f.node(p, q, t));
                if (std::any_of(line.nodes.begin() + 1, line.nodes.end() - 1,
                                [&](Id v) { return bool(crossed[v]); }))
                    continue;
                const int pn = p + 1 < f.np ? p + 1 : p - 1;
                const double tolerance = 1e-3 * (x[f.node(pn, q, 0)] - x[w]).norm();
                append_wall_normals(body, x[w], side, tolerance, line.normals);
                if (line.normals.empty()) continue;
                line.layers = layers_that_fit(line_length(grid, f, p, q), f.depth - 1, law);
                if (line.layers == 0) continue;
                if (line.normals.size() > 1) {
                    line.crease_step = unit_offset(body, x[w], side, tolerance);
                    if (!line.crease_step) continue;
                }
                lines.push_back(std::move(line));
            }
    }
    return lines;
}

}  // namespace

LayerHeightsResult restore_layer_heights(BlockGrid& grid, const ImplicitFunction& body,
                                         const WallLayers& law) {
    LayerHeightsResult result;
    if (law.layers <= 0) return result;
    HexMesh mesh = to_hex_mesh(grid);
    const Adjacency around(mesh);
    std::vector<Vec3>& x = mesh.points;
    // No cell falls below the grid's worst.
    const std::vector<double> sj = scaled_jacobians(mesh);
    const double floor = sj.empty() ? 0 : *std::min_element(sj.begin(), sj.end());
    const std::vector<double> d = layer_heights(law);
    const std::vector<LayerLine> lines = layer_lines(grid, body, law);
    const auto is_off = [&](const LayerLine& line) {
        const Vec3& x0 = x[line.nodes[0]];
        for (int m = 1; m <= line.layers; ++m)
            if (!line.on(x0, x[line.nodes[m]], d[m], 0.05 * (d[m] - d[m - 1]))) return true;
        return false;
    };
    const auto first_within = [&](const LayerLine& line) {
        return line.on(x[line.nodes[0]], x[line.nodes[1]], d[1], 0.1 * d[1]);
    };
    std::vector<char> off(lines.size()), moved(lines.size(), 0);
    for (size_t l = 0; l < lines.size(); ++l) {
        off[l] = is_off(lines[l]);
        result.lines += off[l];
        result.within_before += off[l] && first_within(lines[l]);
    }
    std::vector<Id> nodes;
    std::vector<Vec3> kept, target;
    for (int sweep = 0, moves = 1; sweep < 8 && moves > 0; ++sweep) {
        moves = 0;
        for (size_t l = 0; l < lines.size(); ++l) {
            const LayerLine& line = lines[l];
            if (!off[l] || !is_off(line)) continue;
            const int layers = line.layers;
            const Vec3 x0 = x[line.nodes[0]];
            // The direction the layer nodes go out along from x0, d_m of it to node m. On a
            // smooth wall: the ray through node M (the line's lean kept, not each node's offset
            // along the wall, which over a thinner layer would shear its cells). At a crease or
            // corner: the step that is 1 above every piece (as the layers were laid there).
            Vec3 step;
            if (line.crease_step) {
                step = *line.crease_step;
            } else {
                const Vec3 e = x[line.nodes[layers]] - x0;
                const double up = e.dot(line.normals[0]);
                if (!(up > 0.2 * e.norm())) continue;
                step = e / up;
            }
            // Layer nodes onto their heights, the next `layers` nodes by node M's displacement
            // decreasing linearly, the far end kept.
            const int last = line.last();
            nodes.assign(line.nodes.begin() + 1, line.nodes.begin() + last + 1);
            if (!std::all_of(nodes.begin(), nodes.end(),
                             [&](Id v) { return grid.kinds[v] == VertexKind::interior; }))
                continue;
            kept.clear(), target.clear();
            for (Id v : nodes) kept.push_back(x[v]);
            const Vec3 top = x0 + d[layers] * step - kept[layers - 1];
            for (int t = 1; t <= last; ++t)
                target.push_back(
                    t <= layers
                        ? Vec3(x0 + d[t] * step)
                        : Vec3(kept[t - 1] +
                               (1.0 - double(t - layers) / double(last - layers + 1)) * top));
            const Score before = score_of(mesh, around, nodes);
            // The whole way, else half of it: lines side by side off their heights (a patch
            // given back) each leave their neighbour's cells sheared when moved alone, and come
            // down together over the sweeps.
            for (const double share : {1.0, 0.5}) {
                for (size_t i = 0; i < nodes.size(); ++i)
                    x[nodes[i]] = kept[i] + share * (target[i] - kept[i]);
                const Score after = score_of(mesh, around, nodes);
                if (after.inverted <= before.inverted &&
                    after.inverted_tets <= before.inverted_tets &&
                    after.refused <= before.refused && after.skewed <= before.skewed &&
                    after.lowest >= std::min(before.lowest, floor)) {
                    moved[l] = 1, ++moves;
                    break;
                }
                for (size_t i = 0; i < nodes.size(); ++i) x[nodes[i]] = kept[i];
            }
        }
    }
    for (size_t l = 0; l < lines.size(); ++l) {
        result.moved += moved[l];
        result.within_after += off[l] && first_within(lines[l]);
    }
    grid.points = std::move(mesh.points);
    return result;
}

}  // namespace hexmesh

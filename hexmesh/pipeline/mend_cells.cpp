#include "hexmesh/pipeline/mend_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/mesh_quality.h"
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

// The cells around a node as a move is judged: how many cells the solver refuses (margin <= 0),
// then how many of their faces it refuses (skewness over max_solver_skewness; each face once,
// also between two of these cells), then the smallest margin, a refused face's being
// (max - skewness) / max. A move may not trade a refused cell for an accepted one that falls,
// nor a skewed face for a refused cell.
struct Score {
    int refused = 0, skewed = 0;
    double lowest = std::numeric_limits<double>::infinity();
    bool better_than(const Score& s) const {
        if (refused != s.refused) return refused < s.refused;
        if (skewed != s.skewed) return skewed < s.skewed;
        return lowest > s.lowest + 1e-12;
    }
};

Score score_at(const HexMesh& mesh, const Adjacency& around, Id v) {
    Score s;
    const auto [first, end] = around.of(v);
    // The centres of the cells around v, each computed once: a face between two of them
    // needs both.
    std::vector<Vec3> centres;
    for (const Id* c = first; c != end; ++c) centres.push_back(hex_centre(mesh.corners(*c)));
    for (const Id* c = first; c != end; ++c) {
        const std::array<Vec3, 8> p = mesh.corners(*c);
        const double m = solver_margin(p);
        s.refused += !(m > 0);
        s.lowest = std::min(s.lowest, m);
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
                s.lowest = std::min(s.lowest, (max_solver_skewness - skew) / max_solver_skewness);
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

struct RoundResult {
    Id moves = 0;         // nodes moved
    bool trying = false;  // some node still had a step worth trying
};

// One round over `nodes`: each movable node whose margin is not yet `o.enough` tries a step of
// step[i] along the six axis directions (a slip node's trial projected onto u = 0) and takes
// the best if it is better; a node that finds none halves its step, down to o.last_step edges.
RoundResult mend_round(HexMesh& mesh, const Adjacency& around, const std::vector<VertexKind>& kinds,
                       const ImplicitFunction& body, const std::vector<Id>& nodes,
                       const std::function<bool(Id)>& movable, const MendOptions& o,
                       std::vector<double>& step) {
    static const std::array<Vec3, 6> directions = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                                                   -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
    RoundResult r;
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Id v = nodes[i];
        if (!movable(v) || step[i] <= 0) continue;
        const Score before = score_at(mesh, around, v);
        if (before.lowest > o.enough) continue;
        const double edge = mean_edge_at(mesh, around, v);
        if (step[i] < o.last_step * edge) continue;
        r.trying = true;
        const Vec3 start = mesh.points[v];
        Vec3 best = start;
        Score best_score = before;
        for (const Vec3& d : directions) {
            Vec3 x = start + step[i] * d;
            if (kinds[v] == VertexKind::slip) x = project_to_surface(body, x, edge).point;
            mesh.points[v] = x;
            const Score m = score_at(mesh, around, v);
            if (m.better_than(best_score)) best = x, best_score = m;
        }
        mesh.points[v] = best;
        if (best != start)
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
        for (int round = 0; round < o.rounds; ++round) {
            const RoundResult r =
                mend_round(mesh, around, grid.kinds, body, nodes, movable, o, step);
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

}  // namespace hexmesh

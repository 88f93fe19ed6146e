#include "volume/refine.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"

namespace hexmesh {
namespace {

// A coarse edge (2 ids, then padding) or face (4 ids), sorted: the key of its new node.
using EntityKey = std::array<Id, 4>;  // BlockRefiner::Key

// Whether a line turns by more than 45 degrees at b (from a to b to c): a crease of the wall
// the line follows, where the map from the index is not smooth.
bool kinked(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = b - a, v = c - b;
    return u.dot(v) < std::cos(45 * 3.14159265358979323846 / 180) * u.norm() * v.norm();
}

// Fills the odd entries of a fine line whose even entries (the coarse samples) are set:
// x(m + 1/2) by cubic Lagrange in the index where two samples lie on each side, quadratic at
// the ends, linear on a 2-sample line. A sample where the line turns sharply (kinked) ends
// the stencils on either side of it, as a line end does: the map is smooth only between such
// creases, and a stencil across one overshoots by a fraction of a cell, which is more than
// a boundary layer's thickness. at(f) is the fine entry f of the line.
template <class At>
void interpolate_line(int coarse_count, At&& at) {
    const int n = coarse_count;
    auto sample = [&](int m) -> const Vec3& { return at(2 * m); };
    // Whether the line is smooth through sample m: an inner sample where it does not turn.
    auto smooth_at = [&](int m) {
        return m > 0 && m + 1 < n && !kinked(sample(m - 1), sample(m), sample(m + 1));
    };
    bool left = false;  // smooth_at(0); each interval's right end is the next one's left
    for (int m = 0; m + 1 < n; ++m) {
        Vec3& mid = at(2 * m + 1);
        const bool right = smooth_at(m + 1);
        if (left && right) {
            mid = (9 * (sample(m) + sample(m + 1)) - sample(m - 1) - sample(m + 2)) / 16;
        } else if (right) {
            mid = (3 * sample(m) + 6 * sample(m + 1) - sample(m + 2)) / 8;
        } else if (left) {
            mid = (3 * sample(m + 1) + 6 * sample(m) - sample(m - 1)) / 8;
        } else {
            mid = 0.5 * (sample(m) + sample(m + 1));
        }
        left = right;
    }
}

// Which ends of a block's grid lines along one index direction lie on a wall (a block face
// of patch "wall"): where their boundary layer grows from.
struct WallEnds {
    bool first = false, last = false;
};

// The largest offset of a new node from its coarse cell's chord, in chord lengths: that of an
// arc turning by 45 degrees over the cell, (1/2) tan(45 / 4 degrees), the turn at which a line
// is kinked at a sample and its stencils stop (a cell turning more than that between samples
// that are not kinked, a long cell beside short ones, is flattened to it). A stencil in the
// index across cells of very different lengths overshoots by a share of the long ones: next
// to a boundary layer 10^5 times thinner than the cells beyond (a first height of 1e-7 under
// a coarse wall), up to 3e-3 off a chord of 1.4e-3, and the refined cells crossed.
constexpr double max_sag = 0.09946;

// Fills the odd entries of a wall-normal line (see refine.h) whose even entries are set: first
// as interpolate_line does, then each new node is moved along the chord of its coarse cell
// m (from sample m to m + 1, length L_m) to the fraction the refined law gives, keeping its
// offset across the chord (the line's curvature) up to max_sag L_m. Cell m is split into two cells
// of ratio rho_m = sqrt(L_m / L_w), L_w the cell next to it on the wall side (for the wall cell,
// sqrt(L_o / L_m), L_o the cell beyond it): each coarse step from one cell to the next becomes
// two fine steps of its square root, and the fine cell on the wall side is L_m / (1 + rho_m)
// long. The ratios do not stop at kinks as the stencils do: a line that turns sharply keeps
// its spacing, and a ratio that changed there would jump between neighbouring lines. With
// walls at both ends a cell takes the nearer one (the middle cell of an odd count is halved).
template <class At>
void interpolate_wall_line(int coarse_count, WallEnds wall, At&& at) {
    const int n = coarse_count;
    interpolate_line(n, at);
    auto sample = [&](int m) -> const Vec3& { return at(2 * m); };
    auto length = [&](int m) { return (sample(m + 1) - sample(m)).norm(); };
    for (int m = 0; m + 1 < n; ++m) {
        // Cell m's wall side: its first end, its last end, or neither (the middle cell
        // between two walls).
        const bool from_first = wall.first && (!wall.last || 2 * m < n - 2);
        const bool from_last = wall.last && (!wall.first || 2 * m > n - 2);
        const int inner = from_first ? m - 1 : m + 1;  // the neighbours towards the wall
        const int outer = from_first ? m + 1 : m - 1;  // and away from it
        auto is_cell = [&](int c) { return c >= 0 && c + 1 < n; };
        double rho = 1;  // the fine ratio, away from the wall
        if ((from_first || from_last) && is_cell(inner))
            rho = std::sqrt(length(m) / length(inner));
        else if ((from_first || from_last) && is_cell(outer))
            rho = std::sqrt(length(outer) / length(m));
        if (!(rho > 0) || !std::isfinite(rho)) rho = 1;                // a cell of zero length
        const double f = from_last ? rho / (1 + rho) : 1 / (1 + rho);  // of the chord from m
        const Vec3 chord = sample(m + 1) - sample(m);
        const double chord2 = chord.squaredNorm();
        Vec3& mid = at(2 * m + 1);
        if (!(chord2 > 0)) {  // a cell of zero length: its new node with its two samples
            mid = sample(m);
            continue;
        }
        Vec3 offset = mid - sample(m) - (mid - sample(m)).dot(chord) / chord2 * chord;
        const double most = max_sag * std::sqrt(chord2);
        if (offset.norm() > most) offset *= most / offset.norm();
        mid = sample(m) + f * chord + offset;
    }
}

// Fills a line: along the wall normal by interpolate_wall_line, else by interpolate_line.
template <class At>
void fill_line(int coarse_count, WallEnds wall, At&& at) {
    if (wall.first || wall.last)
        interpolate_wall_line(coarse_count, wall, at);
    else
        interpolate_line(coarse_count, at);
}

// Whether a node (i, j, k) of a block of dims d lies on one of its faces.
bool on_block_face(const Dims& d, int i, int j, int k) {
    return i == 0 || i == d.ni - 1 || j == 0 || j == d.nj - 1 || k == 0 || k == d.nk - 1;
}

// Positions of the fine nodes of one block (fine dims, flat i fastest; at(m) is node m), by
// tensor-product interpolation: along i on the coarse j, k lines, then along j, then along
// k; along an index direction with a wall face at an end, by interpolate_wall_line. With
// `faces_only`, only the lines that lie in a block face: a node on a face depends on that
// face's nodes alone, so its position is the same bit for bit.
template <class At>
void fine_positions(const BlockGrid& coarse, const Block& block, const Dims& fine, bool faces_only,
                    At&& at) {
    const Dims c = block.nodes;
    WallEnds wall[3];
    for (int d = 0; d < 3; ++d)
        wall[d] = {block.face_patch[2 * d] == "wall", block.face_patch[2 * d + 1] == "wall"};
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int j = 0; j < c.nj; ++j)
            for (int i = 0; i < c.ni; ++i)
                if (!faces_only || on_block_face(fine, 2 * i, 2 * j, 2 * k))
                    at(fine.flat(2 * i, 2 * j, 2 * k)) = coarse.points[block.node(i, j, k)];
    });
    // Along i on (even j, even k); along j on (all i, even k); along k on (all i, all j).
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int j = 0; j < c.nj; ++j)
            if (!faces_only || on_block_face(fine, 1, 2 * j, 2 * k))
                fill_line(c.ni, wall[0],
                          [&](int f) -> Vec3& { return at(fine.flat(f, 2 * j, 2 * k)); });
    });
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int i = 0; i < fine.ni; ++i)
            if (!faces_only || on_block_face(fine, i, 1, 2 * k))
                fill_line(c.nj, wall[1],
                          [&](int f) -> Vec3& { return at(fine.flat(i, f, 2 * k)); });
    });
    tbb::parallel_for(0, fine.nj, [&](int j) {
        for (int i = 0; i < fine.ni; ++i)
            if (!faces_only || on_block_face(fine, i, j, 1))
                fill_line(c.nk, wall[2], [&](int f) -> Vec3& { return at(fine.flat(i, j, f)); });
    });
}

// Where placement moved a new wall node by d (onto the body), the new interior nodes of its
// wall-normal line in the fine block `block` (local ids) follow by d (1 - s / S), s the length
// along the line from the wall and S the whole line's: every cell of a straight line grows by
// the same factor, so the first layer keeps its thickness and the line its growth ratios
// (projection moves a node of the interpolated wall by up to a few percent of a cell, as
// much as a thin first layer). The line's far end does not move. Coarse nodes and nodes of
// other kinds (on a wall, a crease, the far field) stay: movable(m) says which may. A node
// other blocks placed first moves too, but gets their position back afterwards, as every
// shared node does. With `faces_only`, only the lines that lie in a block face. at(m) is
// node m's position.
template <class At, class Movable>
void carry_wall_moves(const Block& block, const std::unordered_map<Id, Vec3>& wall_moves,
                      bool faces_only, At&& at, Movable&& movable) {
    if (wall_moves.empty()) return;
    const Dims& f = block.nodes;
    for (int side = 0; side < 6; ++side) {
        if (block.face_patch[side] != "wall") continue;
        const int d = side / 2, p = (d + 1) % 3, q = (d + 2) % 3, n = f[d];
        if (n < 3) continue;
        auto node = [&](int a, int b, int t) {
            int ijk[3];
            ijk[d] = side % 2 ? n - 1 - t : t;
            ijk[p] = a;
            ijk[q] = b;
            return f.flat(ijk[0], ijk[1], ijk[2]);
        };
        tbb::parallel_for(0, f[q], [&](int b) {
            std::vector<double> s(size_t(n), 0.0);
            for (int a = 0; a < f[p]; ++a) {
                if (faces_only && a > 0 && a < f[p] - 1 && b > 0 && b < f[q] - 1) continue;
                const auto moved = wall_moves.find(node(a, b, 0));
                if (moved == wall_moves.end()) continue;
                // Lengths along the line as interpolated, the wall node where it was.
                Vec3 before = at(node(a, b, 0)) - moved->second;
                for (int t = 1; t < n; ++t) {
                    s[t] = s[t - 1] + (at(node(a, b, t)) - before).norm();
                    before = at(node(a, b, t));
                }
                if (!(s[n - 1] > 0)) continue;
                for (int t = 1; t + 1 < n; ++t) {
                    const Id m = node(a, b, t);
                    if (movable(m)) at(m) += (1 - s[t] / s[n - 1]) * moved->second;
                }
            }
        });
    }
}

// The coarse entity of fine node f (on a block face, so an edge or a face): the coarse ids
// of its 2 or 4 corners, sorted, padded with "no node" (the largest id).
EntityKey entity_key(const Block& block, const int f[3]) {
    constexpr Id none = std::numeric_limits<Id>::max();
    EntityKey key = {none, none, none, none};
    size_t n = 0;
    for (int k = f[2] / 2; k <= (f[2] + 1) / 2; ++k)
        for (int j = f[1] / 2; j <= (f[1] + 1) / 2; ++j)
            for (int i = f[0] / 2; i <= (f[0] + 1) / 2; ++i) {
                assert(n < key.size());
                key[n++ % key.size()] = block.node(i, j, k);
            }
    std::sort(key.begin(), key.end());
    return key;
}

// The kind a new node takes from the block faces it lies on (see refine.h).
VertexKind new_node_kind(const BlockGrid& coarse, const Block& block, const Dims& fine,
                         const int f[3], int odd_count, const EntityKey& key) {
    VertexKind kind = VertexKind::interior;
    for (int d = 0; d < 3; ++d) {
        const int side = f[d] == 0 ? 0 : f[d] == fine[d] - 1 ? 1 : -1;
        if (side < 0) continue;
        const std::string& patch = block.face_patch[2 * d + side];
        if (patch.empty()) continue;
        VertexKind k = VertexKind::fixed;
        if (patch == "wall") {
            const auto on_crease = [&](Id v) {
                return coarse.kinds[v] == VertexKind::feature_edge ||
                       coarse.kinds[v] == VertexKind::corner;
            };
            k = odd_count == 1 && on_crease(key[0]) && on_crease(key[1]) ? VertexKind::feature_edge
                                                                         : VertexKind::slip;
        }
        kind = std::max(kind, k);
    }
    return kind;
}

// Calls f(i, j, k) once for every node on the boundary faces of a block of node dims d.
template <class F>
void for_each_face_node(const Dims& d, F&& f) {
    for (int k = 0; k < d.nk; ++k)
        for (int j = 0; j < d.nj; ++j) {
            if (k == 0 || k == d.nk - 1 || j == 0 || j == d.nj - 1) {
                for (int i = 0; i < d.ni; ++i) f(i, j, k);
            } else {
                f(0, j, k);
                if (d.ni > 1) f(d.ni - 1, j, k);
            }
        }
}

// 2n - 1 nodes per direction (a block without nodes stays without).
Dims fine_dims(const Dims& c) {
    if (c.count() == 0) return {0, 0, 0};
    return {2 * c.ni - 1, 2 * c.nj - 1, 2 * c.nk - 1};
}

// Nodes strictly inside a block of node dims d.
Id inner_nodes(const Dims& d) {
    return Dims{d.ni - 2, d.nj - 2, d.nk - 2}.count();
}

}  // namespace

BlockRefiner::BlockRefiner(const BlockGrid& coarse) : coarse_(coarse) {
    if (coarse.kinds.size() != coarse.points.size())
        throw std::invalid_argument("refine: the grid has " + std::to_string(coarse.kinds.size()) +
                                    " vertex kinds for " + std::to_string(coarse.points.size()) +
                                    " points");
    num_points_ = next_id_ = static_cast<Id>(coarse.points.size());
    for (const Block& block : coarse.blocks) {
        const Dims f = fine_dims(block.nodes);
        for_each_face_node(f, [&](int i, int j, int k) {
            const int odd = (i & 1) + (j & 1) + (k & 1);
            if (odd == 0) return;
            const int idx[3] = {i, j, k};
            const Key key = entity_key(block, idx);
            FaceNode& n = face_nodes_[key];
            n.kind = std::max(n.kind, new_node_kind(coarse, block, f, idx, odd, key));
            if (n.remaining++ == 0) ++num_points_;
        });
        // New nodes inside the block: its inner fine nodes but the coarse ones.
        num_points_ += inner_nodes(f) - inner_nodes(block.nodes);
    }
}

const Block& BlockRefiner::next(size_t b) {
    if (b != next_block_ || b >= coarse_.blocks.size())
        throw std::logic_error("BlockRefiner: blocks are refined once each, in order");
    ++next_block_;
    return coarse_.blocks[b];
}

template <class Visit>
void BlockRefiner::number(const Block& block, const Dims& f, Visit&& visit) {
    for (int k = 0; k < f.nk; ++k)
        for (int j = 0; j < f.nj; ++j) {
            const bool face_row = k == 0 || k == f.nk - 1 || j == 0 || j == f.nj - 1;
            for (int i = 0; i < f.ni; ++i) {
                if (!face_row && i == 1 && !visit.each_inner_node && f.ni > 2) {
                    // The row's inner nodes at once: new but the coarse ones (even i, j, k).
                    const Id coarse_inner = (j % 2 == 0 && k % 2 == 0) ? (f.ni - 3) / 2 : 0;
                    next_id_ += f.ni - 2 - coarse_inner;
                    i = f.ni - 2;
                    continue;
                }
                const Id m = f.flat(i, j, k);
                if ((i & 1) + (j & 1) + (k & 1) == 0) {
                    visit.coarse(m, block.node(i / 2, j / 2, k / 2));
                    continue;
                }
                if (!face_row && i != 0 && i != f.ni - 1) {
                    visit.inner(m, next_id_++);
                    continue;
                }
                const int idx[3] = {i, j, k};
                const FaceNodes::iterator e = face_nodes_.find(entity_key(block, idx));
                assert(e != face_nodes_.end());
                FaceNode& n = e->second;
                const bool first = n.id < 0;
                if (first) n.id = next_id_++;
                visit.face(m, Reached{m, e}, first);
            }
        }
}

template <class At, class Movable>
void BlockRefiner::settle(const Block& fine, const std::vector<Reached>& first,
                          const std::vector<Reached>& again, const Place& place, bool faces_only,
                          At&& at, Movable&& movable) {
    if (place) {
        std::vector<Vec3> moves(first.size());
        tbb::parallel_for(size_t(0), first.size(), [&](size_t n) {
            Vec3& x = at(first[n].m);
            const Vec3 placed = place(x, first[n].e->second.kind);
            moves[n] = placed - x;
            x = placed;
        });
        std::unordered_map<Id, Vec3> wall_moves;
        for (size_t n = 0; n < first.size(); ++n)
            if (moves[n] != Vec3::Zero()) wall_moves.emplace(first[n].m, moves[n]);
        carry_wall_moves(fine, wall_moves, faces_only, at, movable);
    }
    for (const Reached& r : first) r.e->second.x = at(r.m);
    for (const Reached& r : again) at(r.m) = r.e->second.x;
    for (auto* list : {&first, &again})
        for (const Reached& r : *list)
            if (--r.e->second.remaining == 0) face_nodes_.erase(r.e);
}

RefinedBlock BlockRefiner::refine(size_t b, const Place& place) {
    const Block& block = next(b);
    const Dims f = fine_dims(block.nodes);
    const Id count = f.count();

    RefinedBlock out;
    out.fine_points = num_points_;
    std::vector<Vec3>& x = out.grid.points;
    x.resize(size_t(count));
    const auto at = [&](Id m) -> Vec3& { return x[size_t(m)]; };
    fine_positions(coarse_, block, f, false, at);
    out.grid.kinds.assign(size_t(count), VertexKind::interior);
    out.ids.assign(size_t(count), -1);
    out.shared.assign(size_t(count), false);
    out.coarse.assign(size_t(count), false);
    Block& fine = out.grid.blocks.emplace_back();
    fine.name = block.name;
    fine.face_patch = block.face_patch;
    fine.nodes = f;
    fine.node_ids.resize(size_t(count));
    for (Id m = 0; m < count; ++m) fine.node_ids[m] = m;

    // Ids in refine_grid's order; the block-face nodes this block reaches first get placed,
    // the others take the position their first block gave them.
    std::vector<Reached> first, again;
    struct Visit {
        RefinedBlock& out;
        const BlockGrid& coarse_grid;
        std::vector<Reached>&first, &again;
        bool each_inner_node = true;
        void coarse(Id m, Id v) {
            out.ids[m] = v;
            out.grid.kinds[m] = coarse_grid.kinds[v];
            out.coarse[m] = true;
        }
        void inner(Id m, Id id) { out.ids[m] = id; }
        void face(Id m, const Reached& r, bool is_first) {
            const FaceNode& n = r.e->second;
            out.grid.kinds[m] = n.kind;
            out.ids[m] = n.id;
            out.shared[m] = !is_first || n.remaining > 1;
            (is_first ? first : again).push_back(r);
        }
    } visit{out, coarse_, first, again, true};
    number(block, f, visit);
    settle(fine, first, again, place, false, at,
           [&](Id m) { return !out.coarse[m] && out.grid.kinds[m] == VertexKind::interior; });
    return out;
}

void BlockRefiner::skip(size_t b, const Place& place) {
    const Block& block = next(b);
    const Dims f = fine_dims(block.nodes);
    // The block's face nodes alone: their positions, and whether carry_wall_moves may move
    // them (new interior nodes).
    struct FacePoint {
        Vec3 x = Vec3::Zero();
        bool movable = false;
    };
    std::unordered_map<Id, FacePoint> points;
    for_each_face_node(f, [&](int i, int j, int k) { points[f.flat(i, j, k)]; });
    const auto at = [&](Id m) -> Vec3& { return points.find(m)->second.x; };
    fine_positions(coarse_, block, f, true, at);
    std::vector<Reached> first, again;
    struct Visit {
        std::unordered_map<Id, FacePoint>& points;
        std::vector<Reached>&first, &again;
        bool each_inner_node = false;
        void coarse(Id, Id) {}
        void inner(Id, Id) {}
        void face(Id m, const Reached& r, bool is_first) {
            points.find(m)->second.movable = r.e->second.kind == VertexKind::interior;
            (is_first ? first : again).push_back(r);
        }
    } visit{points, first, again, false};
    number(block, f, visit);
    Block fine;
    fine.face_patch = block.face_patch;
    fine.nodes = f;
    settle(fine, first, again, place, true, at,
           [&](Id m) { return points.find(m)->second.movable; });
}

BlockGrid refine_grid(const BlockGrid& coarse) {
    BlockRefiner refiner(coarse);
    BlockGrid fine;
    fine.points = coarse.points;
    fine.kinds = coarse.kinds;
    for (size_t b = 0; b < coarse.blocks.size(); ++b) add_refined_block(fine, refiner.refine(b));
    return fine;
}

}  // namespace hexmesh

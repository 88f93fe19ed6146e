#include "volume/refine.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <limits>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"

namespace hexmesh {
namespace {

// A coarse edge (2 ids, then padding) or face (4 ids), sorted: the key of its new node.
using EntityKey = std::array<Id, 4>;

// Fills the odd entries of a fine line whose even entries (the coarse samples) are set:
// x(m + 1/2) by cubic Lagrange in the index where two samples lie on each side, quadratic at
// the ends, linear on a 2-sample line. at(f) is the fine entry f of the line.
template <class At>
void interpolate_line(int coarse_count, At&& at) {
    const int n = coarse_count;
    for (int m = 0; m + 1 < n; ++m) {
        Vec3& mid = at(2 * m + 1);
        if (n == 2) {
            mid = 0.5 * (at(0) + at(2));
        } else if (m == 0) {
            mid = (3 * at(0) + 6 * at(2) - at(4)) / 8;
        } else if (m == n - 2) {
            mid = (3 * at(2 * n - 2) + 6 * at(2 * n - 4) - at(2 * n - 6)) / 8;
        } else {
            mid = (9 * (at(2 * m) + at(2 * m + 2)) - at(2 * m - 2) - at(2 * m + 4)) / 16;
        }
    }
}

// Positions of the fine nodes of one block (fine dims, flat i fastest), by tensor-product
// interpolation: along i on the coarse j, k lines, then along j, then along k.
std::vector<Vec3> fine_positions(const BlockGrid& coarse, const Block& block, const Dims& fine) {
    std::vector<Vec3> x(fine.count());
    const Dims c = block.nodes;
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int j = 0; j < c.nj; ++j)
            for (int i = 0; i < c.ni; ++i)
                x[fine.flat(2 * i, 2 * j, 2 * k)] = coarse.points[block.node(i, j, k)];
    });
    // Along i on (even j, even k); along j on (all i, even k); along k on (all i, all j).
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int j = 0; j < c.nj; ++j)
            interpolate_line(c.ni, [&](int f) -> Vec3& { return x[fine.flat(f, 2 * j, 2 * k)]; });
    });
    tbb::parallel_for(0, c.nk, [&](int k) {
        for (int i = 0; i < fine.ni; ++i)
            interpolate_line(c.nj, [&](int f) -> Vec3& { return x[fine.flat(i, f, 2 * k)]; });
    });
    tbb::parallel_for(0, fine.nj, [&](int j) {
        for (int i = 0; i < fine.ni; ++i)
            interpolate_line(c.nk, [&](int f) -> Vec3& { return x[fine.flat(i, j, f)]; });
    });
    return x;
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

}  // namespace

BlockGrid refine_grid(const BlockGrid& coarse) {
    BlockGrid fine;
    // At most every fine node of every block is new (shared block-face nodes count twice).
    size_t bound = coarse.points.size();
    for (const Block& block : coarse.blocks) {
        const Dims& c = block.nodes;
        bound += size_t(Dims{2 * c.ni - 1, 2 * c.nj - 1, 2 * c.nk - 1}.count() - c.count());
    }
    fine.points.reserve(bound);
    fine.kinds.reserve(bound);
    fine.points = coarse.points;
    fine.kinds = coarse.kinds;
    std::unordered_map<EntityKey, Id, ArrayHash<Id, 4>> shared;  // new nodes on block faces
    for (const Block& block : coarse.blocks) {
        const Dims& c = block.nodes;
        const Dims f = {2 * c.ni - 1, 2 * c.nj - 1, 2 * c.nk - 1};
        const std::vector<Vec3> x = fine_positions(coarse, block, f);
        Block out;
        out.name = block.name;
        out.face_patch = block.face_patch;
        out.nodes = f;
        out.node_ids.resize(f.count());
        for (int k = 0; k < f.nk; ++k)
            for (int j = 0; j < f.nj; ++j)
                for (int i = 0; i < f.ni; ++i) {
                    const int idx[3] = {i, j, k};
                    const Id flat = f.flat(i, j, k);
                    const int odd = (i & 1) + (j & 1) + (k & 1);
                    if (odd == 0) {
                        out.node_ids[flat] = block.node(i / 2, j / 2, k / 2);
                        continue;
                    }
                    const bool on_face = i == 0 || i == f.ni - 1 || j == 0 || j == f.nj - 1 ||
                                         k == 0 || k == f.nk - 1;
                    const EntityKey key = on_face ? entity_key(block, idx) : EntityKey{};
                    const Id id = static_cast<Id>(fine.points.size());
                    if (on_face) {
                        const auto [it, inserted] = shared.try_emplace(key, id);
                        const VertexKind kind = new_node_kind(coarse, block, f, idx, odd, key);
                        if (!inserted) {
                            out.node_ids[flat] = it->second;
                            fine.kinds[it->second] = std::max(fine.kinds[it->second], kind);
                            continue;
                        }
                        fine.kinds.push_back(kind);
                    } else {
                        fine.kinds.push_back(VertexKind::interior);
                    }
                    fine.points.push_back(x[flat]);
                    out.node_ids[flat] = id;
                }
        fine.blocks.push_back(std::move(out));
    }
    return fine;
}

}  // namespace hexmesh

#include "volume/refined_block.h"

#include <array>
#include <stdexcept>
#include <string>

namespace hexmesh {

namespace {

// A fine block named and patched as `like`, of node dims d: its arrays sized, its node ids
// its own (0, 1, ...), its nodes to be copied in (copy_node).
RefinedBlock block_of_dims(const Block& like, const Dims& d, Id fine_points) {
    RefinedBlock out;
    out.fine_points = fine_points;
    Block& b = out.grid.blocks.emplace_back();
    b.name = like.name;
    b.face_patch = like.face_patch;
    b.nodes = d;
    const size_t count = size_t(d.count());
    b.node_ids.resize(count);
    for (size_t m = 0; m < count; ++m) b.node_ids[m] = Id(m);
    out.grid.points.resize(count);
    out.grid.kinds.resize(count);
    out.ids.resize(count);
    out.shared.resize(count);
    out.coarse.resize(count);
    return out;
}

// Node v of `from` as node m of `to`.
void copy_node(RefinedBlock& to, Id m, const RefinedBlock& from, Id v) {
    to.grid.points[size_t(m)] = from.grid.points[size_t(v)];
    to.grid.kinds[size_t(m)] = from.grid.kinds[size_t(v)];
    to.ids[size_t(m)] = from.ids[size_t(v)];
    to.shared[size_t(m)] = from.shared[size_t(v)];
    to.coarse[size_t(m)] = from.coarse[size_t(v)];
}

}  // namespace

RefinedBlock part_of(const RefinedBlock& block, int axis, int lo, int hi) {
    const Block& whole = block.grid.blocks.at(0);
    const Dims w = whole.nodes;
    if (axis < 0 || axis > 2 || lo < 0 || hi <= lo || hi >= w[axis])
        throw std::invalid_argument("part_of: cells " + std::to_string(lo) + ".." +
                                    std::to_string(hi) + " along a block of " +
                                    std::to_string(w[axis]) + " nodes");
    Dims d = w;
    (axis == 0 ? d.ni : axis == 1 ? d.nj : d.nk) = hi - lo + 1;
    RefinedBlock part = block_of_dims(whole, d, block.fine_points);
    std::array<std::string, 6>& patch = part.grid.blocks[0].face_patch;
    if (lo > 0) patch[size_t(2 * axis)].clear();
    if (hi < w[axis] - 1) patch[size_t(2 * axis + 1)].clear();
    for (int k = 0; k < d.nk; ++k)
        for (int j = 0; j < d.nj; ++j)
            for (int i = 0; i < d.ni; ++i) {
                int at[3] = {i, j, k};
                const bool cut =
                    (at[axis] == 0 && lo > 0) || (at[axis] == d[axis] - 1 && hi < w[axis] - 1);
                at[axis] += lo;
                const Id m = d.flat(i, j, k);
                copy_node(part, m, block, w.flat(at[0], at[1], at[2]));
                if (cut) part.shared[size_t(m)] = true;
            }
    return part;
}

RefinedBlock join_parts(const std::vector<RefinedBlock>& parts, int axis) {
    if (parts.empty() || axis < 0 || axis > 2)
        throw std::invalid_argument("join_parts: no part, or no such axis");
    Dims d = parts[0].grid.blocks.at(0).nodes;
    int& along = axis == 0 ? d.ni : axis == 1 ? d.nj : d.nk;
    along = 1;
    for (const RefinedBlock& p : parts) along += p.grid.blocks.at(0).nodes[axis] - 1;
    RefinedBlock whole = block_of_dims(parts[0].grid.blocks[0], d, parts[0].fine_points);
    whole.grid.blocks[0].face_patch[size_t(2 * axis + 1)] =
        parts.back().grid.blocks[0].face_patch[size_t(2 * axis + 1)];
    int lo = 0;
    for (const RefinedBlock& p : parts) {
        const Dims pd = p.grid.blocks[0].nodes;
        for (int k = 0; k < pd.nk; ++k)
            for (int j = 0; j < pd.nj; ++j)
                for (int i = 0; i < pd.ni; ++i) {
                    int at[3] = {i, j, k};
                    at[axis] += lo;
                    copy_node(whole, d.flat(at[0], at[1], at[2]), p, pd.flat(i, j, k));
                }
        lo += pd[axis] - 1;
    }
    return whole;
}

void add_refined_block(BlockGrid& fine, RefinedBlock&& piece) {
    if (fine.points.size() < size_t(piece.fine_points)) {
        fine.points.resize(size_t(piece.fine_points));
        fine.kinds.resize(size_t(piece.fine_points), VertexKind::interior);
    }
    for (size_t m = 0; m < piece.ids.size(); ++m) {
        fine.points[piece.ids[m]] = piece.grid.points[m];
        fine.kinds[piece.ids[m]] = piece.grid.kinds[m];
    }
    Block& block = fine.blocks.emplace_back(std::move(piece.grid.blocks[0]));
    block.node_ids = std::move(piece.ids);
}

}  // namespace hexmesh

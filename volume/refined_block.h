// One fine block of a refined grid on its own (RefinedBlock), cut into parts along an index
// direction and joined back, and put into the fine grid being assembled.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// One fine block of refine_grid, on its own: a grid of one block whose point m is the block's
// node m (flat, i fastest), so it can be finished (projected, optimized, measured, written)
// and dropped before the next block is made.
struct RefinedBlock {
    BlockGrid grid;            // one block; its node_ids are 0, 1, 2, ...
    std::vector<Id> ids;       // the id of each point in refine_grid's numbering
    std::vector<bool> shared;  // a new node that other blocks (or this one twice) also hold
    std::vector<bool> coarse;  // a node of the coarse grid, at its coarse position
    Id fine_points = 0;        // points of the whole fine grid
};

// The part of a fine block made of its cells [lo, hi) along index direction `axis` (nodes lo
// .. hi), all of them along the other two: its points, kinds, ids, coarse flags and patches
// but on the faces cut, which become interfaces (no patch), their nodes marked shared.
RefinedBlock part_of(const RefinedBlock& block, int axis, int lo, int hi);

// The fine block whose parts, in order along `axis`, are `parts` (part_of undone; the
// nodes on a cut keep the shared flag).
RefinedBlock join_parts(const std::vector<RefinedBlock>& parts, int axis);

// Puts a fine block into the fine grid being assembled (`fine` starts as a copy of the coarse
// grid's points and kinds; the first block sizes it to the whole fine grid): refine_grid is
// BlockRefiner's blocks in order, each added so.
void add_refined_block(BlockGrid& fine, RefinedBlock&& piece);

}  // namespace hexmesh

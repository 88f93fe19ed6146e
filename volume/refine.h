// Uniform nested refinement of a block grid: every hex split into 8, interfaces kept conforming.
#pragma once

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// The grid with every cell split into 8: a block of (ni, nj, nk) nodes becomes
// (2 ni - 1, 2 nj - 1, 2 nk - 1). Nesting: node v < coarse.points.size() of the result is
// coarse node v, at exactly the same position, and sits at the even fine indices (2i, 2j, 2k)
// of every block; so level L is exactly every other node of level L + 1. New nodes are created
// once per coarse entity (edge midpoints keyed by their 2 coarse node ids, face centres by
// their 4, cell centres per cell) and numbered after the coarse nodes, block by block, so
// blocks still share their interface nodes.
//
// Positions: the same smooth map x(xi) sampled at the half-integer indices, by tensor-product
// interpolation along the block's grid lines in index space, one direction after the other
// (i, then j, then k): cubic Lagrange (-1, 9, 9, -1)/16 where a line has two coarse nodes on
// each side, quadratic (3, 6, -1)/8 at line ends, linear on 2-node lines. This keeps curved
// walls curved and a geometric stretching geometric (ratio r becomes ~sqrt(r)). A node shared
// by blocks takes the value of the first block that reaches it (the blocks agree up to
// round-off where their lines coincide).
//
// Kinds: coarse nodes keep theirs. A new node on a block face with patch "wall" is slip
// (feature_edge when it is the midpoint of a wall edge whose two ends are feature_edge or
// corner nodes: the crease runs along that edge), on any other patch ("farfield", ...)
// fixed, else interior; a node on several faces takes the most constrained kind. Blocks keep
// their names and patches. Parallel (TBB) over grid lines and cells.
BlockGrid refine_grid(const BlockGrid& coarse);

}  // namespace hexmesh

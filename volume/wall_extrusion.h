// Boundary-layer nodes laid along the wall normals of a grid: exact first height, growth
// ratio and orthogonality by construction.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/stretching.h"

namespace hexmesh {

// For every wall-normal line of `grid` (volume/wall_lines.h), puts its nodes m = 1 ..
// law.layers at x0 + d_m n, with d_m the law's distances (first_height (1 + g + ... +
// g^(m-1))) and n the unit normal of u = 0 at the wall node x0 pointing into the grid; at a
// crease or corner of the body, n is the step that keeps the node at distance d_m from every
// face meeting there (on their offset surfaces). The nodes beyond are shifted by the
// displacement of node law.layers, decreasing linearly to zero at the line's far end (or,
// with blend > 0, at node law.layers + blend + 1, the rest of the line staying put), so the
// line stays smooth where the layers end. Wall nodes and far ends do not move. Lines at knife
// edges (faces meeting at less than about 30 degrees) are left as they are. Returns, per
// node, whether it is a wall or a layer node (the ones the law now fixes). Lines shorter than
// law.layers + 1 edges keep their last node. Lines that would move a node another line
// (from a different wall node) moves too, or another line's wall node, are left as they are:
// in a single block walled on all sides that is every line, and its layers stay as the grid
// was built. law.layers == 0 leaves the grid as it is.
std::vector<bool> extrude_wall_layers(BlockGrid& grid, const ImplicitFunction& body,
                                      const WallLayers& law, int blend = 0);

}  // namespace hexmesh

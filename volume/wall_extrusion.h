// Boundary-layer nodes laid along the wall normals of a grid: exact first height, growth
// ratio and orthogonality by construction.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/stretching.h"
#include "volume/wall_lines.h"

namespace hexmesh {

// The length of the wall-normal line from the wall node (p, q) of `f`: the sum of its edges.
double line_length(const BlockGrid& grid, const WallFace& f, int p, int q);

// The wall-normal lines of `grid` too short for the whole boundary layer (layers_that_fit):
// how many there are, and the one cut the most (fewest layers, then shortest).
struct ThinWallLines {
    Id lines = 0;  // wall-normal lines
    Id cut = 0;    // of which have fewer than law.layers layers
    int fewest = 0;
    double length = 0;
    Vec3 wall = Vec3::Zero();
};
ThinWallLines thin_wall_lines(const BlockGrid& grid, const WallLayers& law);

// Nodes that lines starting at different wall nodes would both move, or that are one line's
// wall node and another's inner node (a single block walled on several sides: lines from
// opposite faces run through the same nodes, lines from neighbouring faces cross near the
// edges and run along each other's walls); `faces` are wall_faces(grid). Lines through them
// (a node 1 .. depth - 2 marked) are left as they are, here and in restore_layer_heights.
std::vector<bool> crossed_lines(const BlockGrid& grid, const std::vector<WallFace>& faces);

// For every wall-normal line of `grid` (volume/wall_lines.h), puts its nodes m = 1 .. M at
// x0 + d_m n, with M = layers_that_fit(its length) (law.layers unless the body is thin there),
// d_m the law's distances (first_height (1 + g + ... + g^(m-1))) and n the unit normal of
// u = 0 at the wall node x0 pointing into the grid; at a crease or corner of the body, n is the
// step that keeps the node at distance d_m from every face meeting there (on their offset
// surfaces). The nodes beyond are shifted by the displacement of node M, decreasing linearly to
// zero at the line's far end (or, with blend > 0, at node M + blend + 1, the rest of the line
// staying put), so the line stays smooth where the layers end. Wall nodes and far ends do not
// move. Lines at knife edges (faces meeting at less than about 30 degrees) are left as they
// are. Returns, per node, whether it is a wall or a layer node (the ones the law now fixes).
// M is below the line's edge count, so its far end stays. Lines that would move a node another
// line (from a different wall node) moves too, or another line's wall node, are left as they
// are: in a single block walled on all sides that is every line, and its layers stay as the
// grid was built. law.layers == 0 leaves the grid as it is.
std::vector<bool> extrude_wall_layers(BlockGrid& grid, const ImplicitFunction& body,
                                      const WallLayers& law, int blend = 0);

}  // namespace hexmesh

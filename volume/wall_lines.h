// Wall-normal lines of a block grid: the nodes of every "wall" block face and the lines of
// nodes going from them into their block.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

// A "wall" face of a block seen as nodes (p, q) over the face and depth t into the block:
// t = 0 is the wall, t = depth - 1 the opposite face.
struct WallFace {
    const Block* block;
    int axis;            // index direction normal to the face (0 = i, 1 = j, 2 = k)
    bool max_side;       // imax, jmax or kmax
    int axis_p, axis_q;  // the two other index directions, ascending
    int np, nq, depth;   // node counts along p, q and into the block

    Id node(int p, int q, int t) const {
        std::array<int, 3> ijk;
        ijk[axis] = max_side ? depth - 1 - t : t;
        ijk[axis_p] = p;
        ijk[axis_q] = q;
        return block->node(ijk[0], ijk[1], ijk[2]);
    }
    Id lines() const { return Id(np) * nq; }
};

// Any face of a block seen so (whatever its patch).
WallFace block_face(const Block& block, BlockFace face);

// Wall faces in block order, then BlockFace order; faces one node thick are skipped.
std::vector<WallFace> wall_faces(const BlockGrid& grid);

// The wall faces of one block, in BlockFace order.
std::vector<WallFace> wall_faces(const Block& block);

// +1 when the grid lies on the u > 0 side of the face (exterior grid), -1 when on u < 0:
// the majority sign of u at the middle nodes of the face's lines.
double grid_side(const WallFace& f, const std::vector<Vec3>& points, const ImplicitFunction& body);

// Appends to `normals` the unit normals, oriented by `side` (+1: out of the body, -1: into
// it), of the smooth pieces of `body` active at x0 within `tolerance` that are not within
// same_normal_degrees of one already there: one at a smooth place, two at a crease, three or
// more at a corner. Pieces with a zero or non-finite gradient are skipped.
void append_wall_normals(const ImplicitFunction& body, const Vec3& x0, double side,
                         double tolerance, std::vector<Vec3>& normals);

// The least-norm step t with n_i . t = 1 for the normals n_i of append_wall_normals at x0:
// x0 + d t lies at distance d from each active piece's plane, i.e. on the offset surfaces.
// One piece: its normal; a crease: along the bisector, 1 / cos(half the angle) long; a
// corner: the corner of the three offset planes. nullopt where that step would be degenerate
// (a knife edge), longer than 4, or inconsistent (four or more pieces whose offset planes do
// not meet in one point: a pyramid's apex), or the wall has no normal.
std::optional<Vec3> unit_offset(const ImplicitFunction& body, const Vec3& x0, double side,
                                double tolerance);

}  // namespace hexmesh

// The core blocks of an O-H grid in cube coordinates: one box, or a column around an axis
// with four ring pieces, so circles around that axis can run along grid lines.
#pragma once

#include <array>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "volume/axial_rings.h"

namespace hexmesh {

// Core blocks over node ids 0 .. t.size()-1, every block right-handed in (i, j, k). A node's
// cube coordinates t lie in [-1, 1]^3 (the parameters of cube_ray in volume/cube_sphere.h);
// the cube's surface |t|_inf = 1 carries the wall faces, which the wall blocks extrude.
struct CoreLayout {
    struct WallFace {
        int block;  // index in blocks
        BlockFace face;
        int side;  // index in cube_patches of the cube face it lies on
    };
    std::vector<Block> blocks;
    std::vector<Vec3> t;               // cube coordinates of each core node
    std::vector<WallFace> wall_faces;  // in block order, then BlockFace order
};

// One box block "core" of n^3 cells at the equiangular coordinates of the lattice [0, n]^3
// (volume/cube_sphere.h: equiangular), node ids in lattice order (i fastest). Its six faces
// are the wall faces.
CoreLayout one_block_core(int n);

// The inner edge of a frame `frame` cells wide along the edges of a cube face of n cells per
// edge (equiangular): the rings' last radius. 1 without a frame.
double axial_frame_edge(int n, int frame);

// The core O-gridded around the rings' axis, a prism along it over a cross-section of the
// cube's faces across it: a column (m x m cells, m = n - 2 frame), four ring pieces from the
// column to the frame's inner square (rings.cells() x m), and a frame `frame` cells wide
// along the cube's edges: four sides (frame x m) and four corners (frame x frame), so the
// cube's corners keep one cell per face. Blocks "core_column", "core_ring_xmax",
// "core_frame_xmax", "core_frame_xmax_ymax", ... (named by the cube faces they reach), n cells
// along the axis, equiangular. Wall faces: every piece's two ends and the pieces' faces on the
// cube's sides. Node ids: the cross-section's nodes, layer by layer along the axis.
CoreLayout axial_core(int n, int frame, const AxialRings& rings);

}  // namespace hexmesh

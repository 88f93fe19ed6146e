// The core blocks of an O-H grid in cube coordinates: one box, or a column around an axis
// with four ring pieces, so circles around that axis can run along grid lines.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"

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

// Rings around `axis` in the two cube faces across it, as the axial core lays them out. In the
// plane of those faces (the other two cube coordinates, b and c): a central square
// |b|, |c| <= column = radius[0], then rings s = 1 .. cells, ring s at distance radius[s] from the
// axis along b and c. roundness[s] blends ring s from the square |b|, |c| = radius[s] (0) to the
// circle of that radius (1); the first ring is the column's square, the last the frame's
// inner square (roundness 0 at both; axial_frame_edge).
struct AxialRings {
    int axis = 2;
    std::vector<double> radius;     // cells + 1 values, radius[0] the column's half-width
    std::vector<double> roundness;  // cells + 1 values in [0, 1]
    int cells() const { return int(radius.size()) - 1; }
    double column() const { return radius.front(); }  // the column's half-width
};

// The inner edge of a frame `frame` cells wide along the edges of a cube face of n cells per
// edge (equiangular): the rings' last radius. 1 without a frame.
double axial_frame_edge(int n, int frame);

// Rings with `cells` cells, evenly spaced from a column of half-width outer / 2 to `outer`,
// round in the middle (roundness sin(pi s / cells)) as far as they stay nested: each ring
// reaches further along the diagonals than the one inside it by at least a quarter of its step
// along the axes (a circle reaches less far than a square; fitted rings are held to the same).
AxialRings even_axial_rings(int axis, int cells, double outer);

// The creases of a body around an axis, as seen from `centre` by the rays ray(t) through the
// two cube faces across the axis: along the 8 half-lines t = w d +- axis (d = +-b, +-c,
// 0 < w < 1) to the faces' edge midpoints, and the 8 half-lines t = v (d + d') +- axis to
// their corners, the rays are placed on u = 0 (volume/surface_placement.h) and the creases
// crossed are found (surface/implicit_features.h) and located exactly; those within 0.05 of
// the axis or of `outer` (the frame, where the patch edges are) are left out. Throws
// std::invalid_argument when a ray misses u = 0 (the body is not star-shaped).
struct AxialCreases {
    std::vector<double> radius;  // w of each crease along the edge-midpoint half-lines, ascending
    std::vector<double> reach;   // its distance from the axis along the diagonals (t plane)
    std::vector<int> seen;       // on how many of the 8 edge-midpoint half-lines it lies
    std::vector<double> w;       // the samples of w
    std::vector<Vec3> meridian;  // the wall at those samples along the first half-line
};
AxialCreases find_axial_creases(const ImplicitFunction& body, const Vec3& centre,
                                const std::function<Vec3(const Vec3&)>& ray, int axis, double outer,
                                double length_scale);

// Rings fitted to the creases around the axis: each crease inside `outer` gets a ring through
// it along the edge-midpoint half-lines, as round as the crease (circle: reach = radius;
// square: reach = sqrt(2) radius); in between, the rings' reach along the diagonals grows
// evenly with their radius, from the column's square to the frame's. The column is half the
// first crease's radius (at most outer / 2); the other rings are spread evenly in arc length
// along the wall between the creases. At most cells - 1 creases are fitted, nearest the axis
// first; without creases, even_axial_rings.
AxialRings fit_axial_rings(const AxialCreases& creases, int axis, int cells, double outer);

// The axis whose round creases run around it: the one with the most creases met on at least
// 4 of their 8 edge-midpoint half-lines (all four of one end, say) and reaching along the
// diagonals less than 1.2 times their radius (circles, not squares: a square crease around an
// axis runs along the lines of one core block's patch, corners included); -1 when no axis
// has one.
int choose_axis(const std::array<AxialCreases, 3>& creases);

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

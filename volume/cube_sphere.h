// The cube-sphere patch layout shared by the O-H and O grids: six patches, one per cube face.
#pragma once

#include <array>
#include <vector>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// A point (a, b, c) of the lattice [0, n]^3 of a cube with n cells per edge.
using LatticePoint = std::array<int, 3>;

// One patch per cube face: the outward axis, its side, and the two in-face axes taken as
// (i, j) so that (i, j, outward) is right-handed. A block built on a patch with k growing
// outwards (away from the centre) is therefore right-handed in (i, j, k).
struct CubePatch {
    const char* side;  // "xmin", "xmax", ..., "zmax": block names are a prefix plus this
    int axis;          // 0, 1, 2: the axis normal to the face
    bool max_side;     // the face lies on the + side of that axis
    int axis_i, axis_j;
};
inline constexpr std::array<CubePatch, 6> cube_patches = {{
    {"xmin", 0, false, 2, 1},
    {"xmax", 0, true, 1, 2},
    {"ymin", 1, false, 0, 2},
    {"ymax", 1, true, 2, 0},
    {"zmin", 2, false, 1, 0},
    {"zmax", 2, true, 0, 1},
}};

// The boundary points of the lattice [0, n]^3, i.e. the nodes of the six n x n patches with
// every shared point (patch edges and corners) counted once: 6 n^2 + 2 points, numbered in
// lattice order (a fastest, then b, then c).
struct CubeSurfaceLattice {
    int n = 0;
    Dims lattice;                      // (n+1)^3 nodes
    std::vector<Id> number;            // lattice.count(): surface number, -1 inside the cube
    std::vector<LatticePoint> points;  // surface number -> lattice point

    Id size() const { return Id(points.size()); }
    Id number_of(const LatticePoint& p) const { return number[lattice.flat(p[0], p[1], p[2])]; }
    // Lattice point of node (i, j) of a patch, 0 <= i, j <= n.
    LatticePoint patch_point(const CubePatch& patch, int i, int j) const;
};

CubeSurfaceLattice make_cube_surface_lattice(int n);

// The lattice's 6 n^2 quads by surface number, patch by patch, j then i: nodes (i, j),
// (i + 1, j), (i + 1, j + 1), (i, j + 1), counter-clockwise seen from outside the cube.
std::vector<std::array<Id, 4>> cube_surface_quads(const CubeSurfaceLattice& lattice);

// The cube coordinates t in [-1, 1]^3 of a lattice point, equiangular: t[d] = tan(pi/4
// (2 p[d]/n - 1)). Rays through the points of one patch are evenly spread in angle.
Vec3 equiangular(const LatticePoint& p, int n);

// The ray of cube coordinates t: half[d] * t[d] (the cube stretched to a box of these half
// extents; its corners on the box's diagonals).
Vec3 cube_ray(const Vec3& t, const Vec3& half);

// Where the cube's 8 corners go, relative to the centre: corner c = (a, b, c) in {0, n}^3 is
// entry (a > 0) + 2 (b > 0) + 4 (c > 0).
using CubeCorners = std::array<Vec3, 8>;

// The ray of cube coordinates t with the cube's corners sent to `corners` (each in its own
// octant): their trilinear blend at t. With the corners (+-half[0], +-half[1], +-half[2]) it
// is the ray above; with a box-like body's own corners the patch corners and edges go to the
// body's.
Vec3 cube_ray(const Vec3& t, const CubeCorners& corners);

// Equiangular cube-sphere coordinates of a lattice point: cube_ray(equiangular(p, n), half).
// With half = (1,1,1) the rays through the points of one patch are evenly spread in angle;
// other half extents stretch the cube to a box (the patch corners lie on its diagonals).
Vec3 cube_sphere_ray(const LatticePoint& p, int n, const Vec3& half);

// The same with the cube's corners sent to `corners`: cube_ray(equiangular(p, n), corners).
Vec3 cube_sphere_ray(const LatticePoint& p, int n, const CubeCorners& corners);

}  // namespace hexmesh

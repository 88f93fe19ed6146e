// The O-H ("butterfly") interior grid: a core box block plus six wall blocks, or a core
// O-gridded around an axis (column, rings, frame) with its wall blocks.
#pragma once

#include <functional>
#include <optional>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/stretching.h"
#include "volume/wall_paths.h"

namespace hexmesh {

struct OHGridOptions {
    int cells_per_edge = 20;  // cells along each edge of the core box and of each wall patch
    int wall_cells = 10;      // cells across each wall block, from the core to the wall
    double core_size = 0.45;  // core box: this fraction of the rays' box (bounds or corners)
    WallLayers wall_layers;   // law of the cells next to the wall (layers = 0: uniform)
    // The points of a grid made with the same options (e.g. after its wall grid was
    // optimized on u = 0): its wall nodes are taken as they are instead of the radial
    // projections, and the lines built from them. nullptr: radial projection.
    const std::vector<Vec3>* wall_from = nullptr;
    std::optional<Vec3> centre;  // default: centre of the body's bounds
    // A box-like body, with exactly one sharp corner in each octant around the centre (found
    // near the wall nodes), or a box at any angle (body_corners_by_octant in
    // volume/feature_snapping.h), gets the patch corners there: the rays span the hexahedron of
    // its corners (cube_sphere_ray with CubeCorners) instead of the bounds' box, so the
    // patch edges can follow its edges. With wall_from: when the given wall's 8 patch-corner
    // nodes are such corners (as that grid made them). false: always the bounds' box.
    bool patch_corners_on_body_corners = true;
    // -1: one core block. 0, 1, 2: the core, and the two patches across this axis, O-gridded
    // around the axis through the centre (volume/core_layout.h: axial_core), with rings fitted
    // to the body's creases around it (the wall's; the core's nodes lie halfway between those
    // and even rings): for circular edges around the axis (a cylinder on a box, a body of
    // revolution), which then run along grid lines. choose_o_h_axis picks one.
    int axis = -1;
    int ring_cells = 0;   // with an axis: cells across the rings (0: (n+1)/2)
    int frame_cells = 1;  // with an axis: cells across the frame along the cube's edges
    // For a body that is not star-shaped around the centre (one core block only): the wall
    // lattice as placed elsewhere (CubeSurfaceLattice numbering, e.g. through a map of the
    // surface onto the sphere) instead of the radial projections, and the core box's half
    // extents in geometry units (instead of core_size times the rays' box). The lines from the
    // core to such a wall may leave the body or turn back: the optimizer's untangling is left
    // to straighten them, and no line is refused.
    const std::vector<Vec3>* wall_nodes = nullptr;
    std::optional<Vec3> core_half;
    // With such a wall: the path of each of its nodes (given the wall nodes, in lattice order)
    // in to a surface star-shaped around the centre that holds the core box, e.g. a level of
    // the body's interior potential (volume/wall_paths.h). Each line then runs along its path
    // and on straight to its core node, its nodes laid by place_nodes_on_paths
    // (volume/path_lines.h: the boundary layer along the path, the next layers on its levels,
    // the rest on to the core node). A path of one point, or with no room for the boundary
    // layer and one cell beyond it, gives a straight line from its wall node. Empty: straight
    // lines from every wall node to its core node.
    std::function<WallPaths(const std::vector<Vec3>& wall)> paths;
};

// Grid of the body's interior. Blocks: "core" (n^3 cells) and "wall_xmin", "wall_xmax", ...,
// "wall_zmax" (n x n x wall_cells cells, k = 0 on the core, k = wall_cells on the wall). With
// an axis, say z: the core blocks "core_column", "core_ring_xmax", ..., "core_frame_xmax",
// ..., "core_frame_xmax_ymax", ... (volume/core_layout.h: axial_core), each end patch the
// same pieces ("wall_zmax_column", "wall_zmax_ring_xmax", ...), each side the frame's side
// "wall_xmax" (or ring piece, without a frame) and its two corners ("wall_xmax_frame_xmax_ymax").
// Every block is right-handed in (i,j,k); the wall blocks' kmax faces form patch "wall". Wall nodes
// are the cube-sphere (equiangular) directions from the centre, scaled by the body's half extents
// (or spanning its corners, see patch_corners_on_body_corners), projected radially onto u = 0 (kind
// slip); the wall-normal lines are straight segments from the core box to the wall carrying the
// WallLayers distribution; the core interior is filled by TFI. Throws std::invalid_argument on bad
// options or a body that is not star-shaped.
BlockGrid make_o_h_grid(const ImplicitFunction& body, const OHGridOptions& options);

// The axis to O-grid the core around (OHGridOptions::axis) for these options: the one whose
// creases, seen through the cube faces across it by the grid's rays, run around it
// (volume/axial_creases.h: find_axial_creases, choose_axis), as a cylinder's circles on a box do;
// -1 (one core block) for a body without such creases, a smooth one among them.
int choose_o_h_axis(const ImplicitFunction& body, const OHGridOptions& options);

// The options' core_size, or half the smallest fraction of the way from the centre to the wall
// along make_o_h_grid's rays (its wall placed as it places it) when the core box would
// otherwise reach within a tenth of that way of the wall: the core of a body that is
// star-shaped but thin or concave near its centre (a cross) then stays inside it. A wall
// placed without rays (wall_nodes, core_half) keeps core_size.
double core_size_within_wall(const ImplicitFunction& body, const OHGridOptions& options);

// Length scale of a grid of the body with n cells per edge: bounds diagonal / (sqrt(3) n).
double grid_length_scale(const ImplicitFunction& body, int cells_per_edge);

}  // namespace hexmesh

// The exterior O-grid: six cube-sphere blocks filling the shell between a body and its far field.
#pragma once

#include <optional>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/far_field_shape.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/stretching.h"
#include "volume/wall_paths.h"

namespace hexmesh {

struct OGridOptions {
    int cells_per_edge = 20;  // n: cells along each edge of each of the six patches (>= 2)
    int layers = 40;          // nk: cells along each wall-normal line, wall to far field
    WallLayers wall_layers;   // law of the cells next to the wall (layers = 0: uniform)
    FarFieldShape far_field = FarFieldShape::sphere;
    // Sphere radius or box half-size, from the centre, in geometry units. It must enclose the
    // body's bounds with a margin of 0.1 bounds diagonal.
    double far_field_size = 10;
    std::optional<Vec3> centre;  // default: centre of the body's bounds; must be inside
    // The points of a grid made with the same options (e.g. after its wall grid was
    // optimized on u = 0): its wall nodes are taken as they are instead of the radial
    // projections, and the lines built from them. nullptr: radial projection.
    const std::vector<Vec3>* wall_from = nullptr;
    // A box-like body (one corner in each octant around the centre, or a box at any angle:
    // body_corners_by_octant in volume/feature_snapping.h; or 8 convex corners, one per
    // octant, spanning a box whose 12 edges lie on its surface, such as the ends of one bar
    // of a cross: convex_corners_by_octant) gets the patch corners on those corners
    // (cube_sphere_ray with CubeCorners) instead of the bounds' box, so the patch edges follow
    // its edges, and a far-field sphere turns with them. With wall_from: when
    // the given wall's 8 patch-corner nodes are such corners (as that grid made them).
    // false: always the bounds' box.
    bool patch_corners_on_body_corners = true;
    // The wall lattice carried in from a far star-shaped surface (for a body that is not
    // star-shaped around the centre: hexmesh/pipeline/exterior_paths.h): its wall is the
    // grid's (unless wall_from is given), its centre the grid's, and each line follows its
    // path instead of leaving the wall along its normal (see make_o_grid). nullptr: the radial
    // construction.
    const WallPaths* paths = nullptr;
};

// Grid of the shell between the body (u = 0) and a far-field sphere or box around `centre`.
//
// Blocks: "shell_xmin", "shell_xmax", "shell_ymin", "shell_ymax", "shell_zmin", "shell_zmax",
// one per cube-sphere patch (cube_patches in volume/cube_sphere.h, in that order), each
// (n+1) x (n+1) x (nk+1) nodes. (i, j) run over the patch (its axis_i, axis_j) and k from the
// wall outwards: k = 0 on the wall (face kmin, patch "wall"), k = nk on the far field (face
// kmax, patch "farfield"); every block is right-handed in (i, j, k). The other four faces of
// each block are interfaces. Blocks share the nodes of their interfaces (one node array of
// (6 n^2 + 2) (nk + 1) points): the node of surface point s (CubeSurfaceLattice numbering)
// on layer k has id k (6 n^2 + 2) + s. Kinds: wall nodes slip, far-field nodes fixed, all
// others interior.
//
// Wall nodes: the equiangular cube-sphere directions from the centre scaled by the body's
// half extents (or spanning its corners, see patch_corners_on_body_corners; as in the O-H
// grid) projected radially onto u = 0, so the body must be star-shaped around the centre.
// Far-field nodes: the equiangular cube-sphere points q of the unit cube, whatever the body's
// proportions, on the sphere (centre + size R q / |q|, R the rotation nearest the map of the
// cube's corners to the body's when the patch corners are on them, else the identity) or the
// box (every block's far-field face is one face of the box, which keeps the world's axes).
// Wall-normal lines: x(tau) = x0 + tau r(tau) m(tau), tau in [0, |far - x0|], m the
// normalized blend (1 - b) normal + b straight of the wall normal at x0 and the direction to
// the far-field node, b = smoothstep(tau / bend): the line leaves the wall along the normal
// (b(0) = b'(0) = 0) and ends on its far-field node. The wall normal is grad u / |grad u|;
// at a crease or corner of the body, the bisector of the faces meeting there, and r blends
// from that step's length in unit_offset (volume/wall_lines.h) to 1, so the line's first
// nodes lie on the faces' offset planes, where extrude_wall_layers lays the boundary layer.
// bend is the whole line where the wall is convex, but round a body with creases at most
// half its bounds diagonal (so the lines of flat faces fan out as soon as those of their
// edges), and shorter where the wall is concave, so that the normals there do not cross
// (concave features finer than the patch lattice are not seen). Nodes: the cell heights
// |x_k - x_(k-1)| are (a_k - a_(k-1)) r, a = wall_distances(length of the line in the law,
// nk, wall_layers), for every cell but the last: the boundary layer has exactly the law's
// first height and growth ratio, on bent lines too; the last cell ends on the far-field node.
// With `paths` (a body that is not star-shaped), the wall nodes are the paths' and the line of
// surface point s follows its path from the wall out to the far surface, then the straight
// segment from there to its far-field node. The boundary layer's nodes lie at the law's
// distances (arc length) along the path; the next ones, up to the far surface, on surfaces of
// equal level of the path's potential (geometric in the level, from each line's level at the
// top of the boundary layer to the far surface's), so the layers do not cross where
// neighbouring paths have very different lengths (one out of a gap, one off a fin); the rest
// grow geometrically along the segment to the far field. Cells are split between the level
// part and the segment by the number of growth-ratio steps each spans. The far-field nodes lie
// radially out from the paths' ends.
// Throws std::invalid_argument, with a message naming the option, on n < 2, nk < 1, a law
// that does not fit the lines (wall_layers.layers >= nk, or a first layer over half a line),
// a far field that does not enclose the body's bounds with the margin, a centre outside the
// body, or a body that is not star-shaped around it.
BlockGrid make_o_grid(const ImplicitFunction& body, const OGridOptions& options);

}  // namespace hexmesh

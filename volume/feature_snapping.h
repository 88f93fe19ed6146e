// Sharp creases and corners of the body captured by a grid's wall nodes.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/cube_sphere.h"

namespace hexmesh {

struct FeatureSnapping {
    Id crease_nodes = 0;  // now VertexKind::feature_edge, on a crease
    Id corner_nodes = 0;  // now VertexKind::corner, on a body corner
};

// Moves slip nodes of `grid` onto the sharp features of `body` (creases and corners of
// analytic and CSG pieces, see surface/implicit_features.h) and changes their kind, so the
// optimizer slides them along the crease or keeps them at the corner. A slip node is taken
// when a crease passes within `fraction` of its shortest wall edge (0.35: the nearest row of
// nodes on each side of a crease, never two rows); each body corner takes only its nearest
// node. A smooth body is left untouched.
FeatureSnapping snap_to_features(BlockGrid& grid, const ImplicitFunction& body,
                                 double fraction = 0.35);

// The corners of `body` (three or more pieces with normals spanning 3D, see
// surface/implicit_features.h) within `reach` of one of `points`, each listed once, in the
// order first found. Empty for a smooth body.
std::vector<Vec3> body_corners_near(const ImplicitFunction& body, const std::vector<Vec3>& points,
                                    double reach);

// The body's corners `found` as the cube's (relative to `centre`, CubeCorners order), when
// there is exactly one in each octant around the centre and none within 1e-3 h of an axis
// plane through it; or, for the 8 corners of a box at an angle, one in each octant of the
// box's own axes (each taken for the world axis nearest it); either way only when the cube's
// edges go to the body's edges (the hexahedron of the corners in that order has 8 positive
// corner tets); nullopt otherwise. With them as
// cube_ray's corners, the patch corners and edges of a grid go to a box-like body's corners
// and edges.
std::optional<CubeCorners> body_corners_by_octant(const Vec3& centre,
                                                  const std::vector<Vec3>& found, double h);

// A box-like body's corners, one per octant around the centre, within h of the wall nodes
// `wall` (body_corners_near, then body_corners_by_octant); nullopt otherwise.
std::optional<CubeCorners> corners_near_wall(const ImplicitFunction& body, const Vec3& centre,
                                             const std::vector<Vec3>& wall, double h);

// The share of the ball of radius r round x inside the body (from 216 directions): 1/2 on a
// smooth wall, 1/4 on a convex edge of 90 degrees, 3/4 on an inner one, 1/8 at a box's corner.
double inside_share(const ImplicitFunction& body, const Vec3& x, double r);

// For an exterior grid of a body with more corners than octants: of the body's corners
// `found` (body_corners_near), one convex corner (a box's corner: its ball of 0.25 h at most a
// fifth inside the body) in each octant around the centre, such that the 12 edges of their
// hexahedron lie on the body's surface (as the patch edges between them then do), the choice
// of largest smallest corner volume (the determinant of the three edges from a corner:
// untwisted, near a box, spanning the body); relative to the centre. A flat cross's 8 patch
// corners through its bounds' box land on its inner vertical edges, where one of the three
// wall cells at each folds round the edge (min scaled Jacobian 0.055 at 20 cells per edge); on
// the 8 ends of one of its bars each cell takes a face at 90 degrees (0.28). Its corners at the
// arms' ends turning the same way round every quadrant (a box turned about its axis) are not
// taken: those edges cut across the air between the arms (0.11). nullopt when an octant has no
// convex corner, no choice qualifies (a cross turned about its axis has both corners of a bar's
// end in one octant) or there are over 2^20 choices.
std::optional<CubeCorners> convex_corners_by_octant(const ImplicitFunction& body,
                                                    const Vec3& centre,
                                                    const std::vector<Vec3>& found, double h);

// The corners of a grid built with its patch corners on body corners, read back from its wall:
// `at[c]` is its wall node at cube corner c (CubeCorners order). They are taken as they are
// (relative to `centre`) when all 8 are corners of `body` (within 1e-6 h) and untwisted, as
// body_corners_by_octant would have made them; nullopt otherwise (the grid's rays went
// through the bounds' box).
std::optional<CubeCorners> corners_at_patch_corners(const ImplicitFunction& body,
                                                    const Vec3& centre,
                                                    const std::array<Vec3, 8>& at, double h);

}  // namespace hexmesh

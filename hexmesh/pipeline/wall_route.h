// How the wall grid of a case's body is placed: radially from a centre the body is
// star-shaped around, or carried in from a far surface that is.
#pragma once

#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/pipeline/spread_on_levels.h"
#include "io/case_file.h"
#include "surface/exterior_potential.h"
#include "untangle/untangle.h"
#include "volume/wall_paths.h"

namespace hexmesh {

class SphereMap;

struct WallRoute {
    Vec3 centre = Vec3::Zero();
    // Not radial: the wall lattice (CubeSurfaceLattice numbering) placed through a map of the
    // body's surface onto the sphere (hexmesh/pipeline/sphere_map.h) and the potential whose
    // gradient lines carry it to its level far_level, which is star-shaped around `centre`
    // (hexmesh/pipeline/exterior_paths.h): out, for an exterior grid; in, for an interior one
    // (none: straight lines to the core). Radial: empty, the builders project rays from
    // `centre`.
    std::shared_ptr<const std::vector<Vec3>> wall;
    std::shared_ptr<const ImplicitFunction> potential;
    // Not radial: the map of the body's surface onto the sphere that placed `wall`, turned to
    // face the body (hexmesh/pipeline/sphere_map.h: aligned_with_body).
    std::shared_ptr<const SphereMap> map;
    // Exterior, made by add_directions: the harmonic extension of the map's directions, whose
    // fibres the lines then follow (none: the potential's gradient lines).
    std::shared_ptr<const HarmonicDirections> directions;
    double far_level = 0;
    // Interior: the core box's half extents, around `centre`, inside the body. With
    // `potential` (add_interior_potential), the lines run in along its gradient lines to its
    // level far_level, then on straight to the core; else straight from the wall to the core.
    std::optional<Vec3> core_half;
    // Radial all the same for a body that is not star-shaped and whose surface u = 0 could not
    // be contoured for the map: why, for the message of a construction that then fails.
    std::string not_star_shaped;
    untangle::UntangleOptions solver;  // of the 2D solves on the far-field sphere and levels
    // Exterior: the lines carried out level by level, repaired where neighbouring gradient
    // lines part or fold (exterior_paths, spread_on_levels); else the gradient lines as they are.
    bool spread_on_levels = false;

    bool radial() const { return !wall; }
    // Through the sphere map, with its lines as first made (along the potential's gradient
    // lines), neither along fibres nor spread on levels: outside, a grid along them that stays
    // tangled is made again along the fibres (run_case.cpp, retry_with_fibres).
    bool along_first_lines() const { return wall && !directions && !spread_on_levels; }
};

// The route of the case's grid (both domains; the single block keeps its own construction):
// - radial from grid.center when given, else from the centre of the body's bounds, when the
//   body is star-shaped around it (every one of 1000 rays crosses u = 0 once): the analytic and
//   star-shaped bodies are placed as a ray from one centre places them;
// - interior: else radial from the body's deepest point (smallest u) when it is star-shaped
//   around that, or from another point as deep around which it is (deepest_candidates, 8 of
//   them: where bars of one thickness meet); else the wall lattice through a map of the
//   surface onto the sphere, around a
//   core cube at the deepest point inside the largest ball there (half-size 0.45 of its
//   radius), the lines in along the gradient lines of the body's interior potential
//   (add_interior_potential) and on straight to the core, or, when its solve fails or it has
//   no star-shaped level, straight from the wall to the core (the optimizer's untangling bends
//   them into what sticks out; so are single lines laid, see OHGridOptions::paths);
// - exterior: else the wall lattice through a map of the surface onto the sphere, and the
//   lines out along the gradient lines of the body's exterior potential
//   (surface/exterior_potential.h) to its lowest level in 0.1, 0.2, ... 0.9 that is star-shaped
//   around the centre of the bounds (or grid.center), rays meeting it within 80 degrees of its
//   normal, and passes at least twice the boundary layer's thickness from the body (along
//   fibres instead once add_directions has run).
// The surface mapped is the surface file's; a body without one (a formula, CSG, points) has its
// surface u = 0 contoured (hexmesh/pipeline/body_surface.h), at 96 lattice cells along its
// longest side, again at 192 when that has handles or pieces, refused when it still has (as a
// file's is), placed radially all the same when no contour comes out.
// The choice, why, and the time of each step (potential, sphere map) go to `log`;
// `cells_per_edge` and `solver` are those of its wall lattice and 2D solves. Throws InputError
// naming the case when grid.center is outside the body (interior only: outside, the centre need
// only see the potential's far level), when no point of it is inside, for handles or several
// pieces of a contour, or when no far level is star-shaped with room for the boundary layer.
WallRoute choose_wall_route(const Case& c, const ImplicitFunction& body,
                            const std::optional<TriangleSurface>& surface, int cells_per_edge,
                            const untangle::UntangleOptions& solver, std::ostream& log);

// The paths of an exterior grid's lines (volume/wall_paths.h) from these wall nodes (the
// route's, or the same moved on u = 0) up the route's potential, along the fibres of its
// directions; their far-field directions
// untangled on the unit sphere; spread out on the potential's levels where they part or fold
// when the route says so (WallRoute::spread_on_levels; what was done to `spread`, if given).
// The route must not be radial.
WallPaths exterior_paths(const WallRoute& route, const std::vector<Vec3>& wall, int cells_per_edge,
                         LevelSpreading* spread = nullptr);

// For an exterior route that is not radial: the harmonic extension outside the body of the
// directions of route.map (its images on the body, the directions from route.centre on the
// potential's box: surface/exterior_potential.h, HarmonicDirections) into route.directions, so
// that exterior_paths runs the lines along its fibres, which do not part where the
// potential's gradient lines do, at its saddles. Logs the solve; false (the route as it was)
// when the solve fails.
bool add_directions(const ImplicitFunction& body, WallRoute& route, std::ostream& log);

// For an interior route that is not radial (choose_wall_route calls it): the body's interior
// potential, 1 on the ball of 0.9 `depth` (the centre's distance to the surface) round
// route.centre (surface/exterior_potential.h),
// and its highest level in tenths star-shaped around the centre, into route.potential and
// route.far_level, so that build_grid lays the lines in along its gradient. Logs the solve;
// false (the route as it was: lines straight to the core) when the solve fails or no level is
// star-shaped.
bool add_interior_potential(const ImplicitFunction& body, double depth, WallRoute& route,
                            std::ostream& log);

// The paths of an interior grid's lines from these wall nodes in along the route's interior
// potential (hexmesh/pipeline/exterior_paths.h: interior_paths). The route must have one.
WallPaths interior_paths(const WallRoute& route, const std::vector<Vec3>& wall, int cells_per_edge);

}  // namespace hexmesh

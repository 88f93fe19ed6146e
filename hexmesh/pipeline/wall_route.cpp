#include "hexmesh/pipeline/wall_route.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "hexmesh/pipeline/body_surface.h"
#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/exterior_paths.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/sphere_map.h"
#include "surface/exact_distance.h"
#include "surface/exterior_potential.h"
#include "surface/level_sets.h"
#include "surface/surface_topology.h"
#include "volume/stretching.h"

namespace hexmesh {
namespace {

constexpr int star_rays = 1000;
// Lattice cells along the longest side of a formula or CSG body's bounds, for its surface
// u = 0 (contour_body).
constexpr int contour_cells = 96;

std::string point(const Vec3& x) {
    return fmt::format("({:.4g}, {:.4g}, {:.4g})", x.x(), x.y(), x.z());
}

// Whether F = c is star-shaped around `centre` (rays sampled every `step`, angles up to
// max_angle_deg); with `crossings`, where each ray crosses it.
bool star_shaped(const ImplicitFunction& f, double c, const Vec3& centre, double step,
                 double max_angle_deg, std::vector<Vec3>* crossings = nullptr) {
    static const std::vector<Vec3> directions = sphere_directions(star_rays);
    const double reach = 1.01 * (f.bounds().size().norm() + (f.bounds().center() - centre).norm());
    return star_shaped_level(f, c, centre, directions, step, reach, max_angle_deg, crossings);
}

// The centre the wall is placed from, what the log calls it, and whether rays from there
// place it (the body is star-shaped around it).
struct Centre {
    Vec3 x;
    std::string what;
    bool radial = false;
};

// grid.center, else the centre of the bounds; for an interior without grid.center, the deepest
// point when the body is not star-shaped around that, or another point as deep around which it
// is (deepest_candidates) (depth: the exact distance to the surface file, made into `exact` once
// the body is known not to be star-shaped, else -u).
Centre choose_centre(const Case& c, const ImplicitFunction& body,
                     const std::optional<TriangleSurface>& surface,
                     std::optional<ExactDistance>& exact, double step, std::ostream& log) {
    const Box3 box = body.bounds();
    Centre centre{c.grid.center.value_or(box.center()),
                  c.grid.center ? "grid.center" : "the centre of its bounds"};
    // Outside, the centre only needs to see the potential's far level.
    if (c.grid.center && c.domain != Domain::exterior && !(body.value(centre.x) < 0))
        throw InputError(
            fmt::format("{}: grid.center {} is not inside the body", c.path, point(centre.x)));
    if (body.value(centre.x) < 0 && star_shaped(body, 0, centre.x, step, 90)) {
        log << fmt::format("  the body is star-shaped around {} {}: wall placed radially\n",
                           centre.what, point(centre.x));
        centre.radial = true;
        return centre;
    }
    // A surface file's SDF is a distance only within a few voxels of the surface.
    if (surface && c.domain != Domain::exterior) exact.emplace(*surface);
    if (c.domain == Domain::exterior || c.grid.center) return centre;
    const auto depth = [&](const Vec3& x) { return exact ? exact->distance(x) : -body.value(x); };
    const DepthLattice lattice = depth_lattice(body, box.diagonal() / 60, depth);
    const std::optional<Vec3> deepest = deepest_point(body, lattice, depth);
    if (!deepest)
        throw InputError(
            fmt::format("{}: no point of the body is inside it (u < 0 nowhere "
                        "on a lattice of a sixtieth of its diagonal)",
                        c.path));
    centre.x = *deepest;
    centre.what = "its deepest point";
    if (star_shaped(body, 0, centre.x, step, 90)) {
        log << fmt::format(
            "  the body is star-shaped around its deepest point {}: wall "
            "placed radially\n",
            point(centre.x));
        centre.radial = true;
        return centre;
    }
    // Bars of one thickness are as deep all along: the body may be star-shaped around another
    // point as deep (where the bars meet), which the rays then place best.
    for (const Vec3& x : deepest_candidates(lattice, 8))
        if (star_shaped(body, 0, x, step, 90)) {
            log << fmt::format(
                "  the body is star-shaped around {}, as deep as its deepest point {}: wall "
                "placed radially\n",
                point(x), point(centre.x));
            centre.x = x;
            centre.radial = true;
            return centre;
        }
    return centre;
}

// The exterior potential of `body` and its first level (in tenths) star-shaped around
// route.centre and at least twice the boundary layer's thickness from the body (distances to
// `surface`, the file's or the contour), into `route`.
void exterior_level(const Case& c, const ImplicitFunction& body, const TriangleSurface& surface,
                    const std::string& what, WallRoute& route, Lap& lap, std::ostream& log) {
    auto potential = std::make_shared<ExteriorPotential>(body);
    log << fmt::format(
        "  the body is not star-shaped around {} {}: exterior potential ({} "
        "unknowns, {} iterations, {:.2f} s)\n",
        what, point(route.centre), potential->unknowns(), potential->iterations(), lap());
    // The lines' boundary layer is laid along them up to their level, then the levels' cells:
    // a level nearer the body than twice the layer's thickness would end lines inside their
    // layer (at a convex tip, where the potential rises fast), its nodes pressed together.
    const double room = 2 * layers_thickness(wall_layers(c));
    std::optional<ExactDistance> exact;
    if (room > 0) exact.emplace(surface);
    double nearest = 0;  // of the last star-shaped level, to the body
    std::vector<Vec3> crossings;
    for (int tenth = 1; tenth <= 9 && route.far_level == 0; ++tenth) {
        if (!star_shaped(*potential, 0.1 * tenth, route.centre, potential->spacing() / 2, 80,
                         &crossings))
            continue;
        nearest = std::numeric_limits<double>::infinity();
        if (room > 0)
            for (const Vec3& x : crossings) nearest = std::min(nearest, exact->distance(x));
        if (nearest >= room)
            route.far_level = 0.1 * tenth;
        else
            log << fmt::format(
                "  its level {:.1f} is star-shaped but passes {:.3g} from the body, nearer than "
                "twice the boundary layer's thickness (2 x {:.3g}): a higher level is tried\n",
                0.1 * tenth, nearest, room / 2);
    }
    if (route.far_level == 0)
        throw InputError(
            nearest > 0
                ? fmt::format(
                      "{}: no level of the exterior potential is star-shaped around {} "
                      "and at least twice the boundary layer's thickness (2 x {:.3g}) from "
                      "the body (the highest star-shaped one passes {:.3g} from it): give a "
                      "thinner boundary layer",
                      c.path, point(route.centre), room / 2, nearest)
                : fmt::format("{}: no level of the exterior potential is star-shaped "
                              "around {}: give grid.center near the middle of the body",
                              c.path, point(route.centre)));
    route.potential = std::move(potential);
}

// -F: the interior potential falls away from its centre, which star_shaped takes as rising.
class Negated : public ImplicitFunction {
  public:
    explicit Negated(const ImplicitFunction& f) : f_(f) {}
    double value(const Vec3& p) const override { return -f_.value(p); }
    Vec3 gradient(const Vec3& p) const override { return -f_.gradient(p); }
    Box3 bounds() const override { return f_.bounds(); }

  private:
    const ImplicitFunction& f_;
};

// The surface mapped onto the sphere, and route.wall: the wall lattice placed through it.
void map_wall(const Case& c, const TriangleSurface& surface, const ImplicitFunction& body,
              int cells_per_edge, WallRoute& route, Lap& lap, std::ostream& log) {
    SphereMapOptions m;
    m.log = &log;
    const SphereMap map = [&] {
        try {
            return map_to_sphere(surface, m);
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("{}: the surface cannot be mapped onto the sphere: {}",
                                         c.path, e.what()));
        }
    }();
    log << fmt::format(
               "  its surface mapped onto the sphere ({} triangles, {} turned over, {:.2f} s)",
               map.surface().triangles.size(), map.inverted(), lap())
        << (!route.core_half
                ? fmt::format("; lines out to the potential's level {:.1f}\n", route.far_level)
            : route.potential
                ? fmt::format("; lines in to the potential's level {:.1f}, then straight to a core "
                              "cube of half-size {:.4g}\n",
                              route.far_level, route.core_half->x())
                : fmt::format("; lines straight to a core cube of half-size {:.4g}\n",
                              route.core_half->x()));
    route.map = std::make_shared<SphereMap>(aligned_with_body(map, route.centre));
    route.wall =
        std::make_shared<std::vector<Vec3>>(wall_from_sphere_map(*route.map, cells_per_edge, body));
}

}  // namespace

WallRoute choose_wall_route(const Case& c, const ImplicitFunction& body,
                            const std::optional<TriangleSurface>& surface, int cells_per_edge,
                            const untangle::UntangleOptions& solver, std::ostream& log) {
    WallRoute route;
    const double step = body.bounds().size().maxCoeff() / 512;  // finer than a file's voxel
    std::optional<ExactDistance> exact;
    const Centre centre = choose_centre(c, body, surface, exact, step, log);
    route.centre = centre.x;
    if (centre.radial) return route;
    // A body without a surface file (a formula, CSG, points): its surface u = 0 contoured for
    // the map onto the sphere, on a finer lattice when parts a lattice cell apart joined or
    // split on the first.
    std::optional<TriangleSurface> contoured;
    if (!surface) {
        Lap contouring;
        SurfaceTopology t;
        int cells = 0;
        try {
            for (const int lattice : {contour_cells, 2 * contour_cells}) {
                cells = lattice;
                contoured = contour_body(body, cells);
                t = surface_topology(*contoured);
                if (t.components.size() == 1 && t.components[0].genus == 0) break;
            }
        } catch (const std::invalid_argument& e) {
            // The first point of u = 0 each ray meets: fine when only rays between the
            // lattice's cross it again.
            route.not_star_shaped = fmt::format("the body is not star-shaped around {} {}",
                                                centre.what, point(route.centre));
            log << "  " << route.not_star_shaped << " and its surface u = 0 was not contoured ("
                << e.what() << "): wall placed radially all the same\n";
            return route;
        }
        const double cell = body.bounds().size().maxCoeff() / cells;
        log << fmt::format(
            "  its surface u = 0 contoured for the map onto the sphere ({} "
            "triangles, lattice of {:.3g}, {:.2f} s)\n",
            contoured->triangles.size(), cell, contouring());
        // What the map cannot take, said as for a surface file.
        if (t.components.size() > 1)
            throw InputError(fmt::format(
                "{}: {} separate bodies (the surface u = 0 contoured on a lattice of {:.3g}; "
                "parts nearer than that count as joined): hexmesh grids one closed body",
                c.path, t.components.size(), cell));
        if (const long long genus = t.components[0].genus; genus > 0)
            throw InputError(fmt::format(
                "{}: genus {}: the surface u = 0 (contoured on a lattice of {:.3g}; parts nearer "
                "than that count as joined) has {} handle{}; hexmesh grids bodies without holes "
                "through them",
                c.path, genus, cell, genus, genus > 1 ? "s" : ""));
    }
    const TriangleSurface& mapped = surface ? *surface : *contoured;
    Lap lap;
    if (c.domain != Domain::exterior) {
        const double depth = exact ? exact->distance(route.centre) : -body.value(route.centre);
        route.core_half = Vec3::Constant(0.45 * depth);
        log << fmt::format("  the body is not star-shaped around {} {} (depth {:.4g}):\n",
                           centre.what, point(route.centre), depth);
        add_interior_potential(body, depth, route, log);
        lap();  // the sphere map's time from here
    } else {
        exterior_level(c, body, mapped, centre.what, route, lap, log);
    }
    map_wall(c, mapped, body, cells_per_edge, route, lap, log);
    route.solver = solver;
    route.solver.log = nullptr;
    return route;
}

WallPaths exterior_paths(const WallRoute& route, const std::vector<Vec3>& wall, int cells_per_edge,
                         LevelSpreading* spread) {
    LevelSpreading done;
    return exterior_paths(
        *route.potential, wall, route.far_level, cells_per_edge, route.centre, route.solver,
        route.spread_on_levels ? (spread ? spread : &done) : nullptr, route.directions.get());
}

bool add_directions(const ImplicitFunction& body, WallRoute& route, std::ostream& log) {
    Lap lap;
    const SphereMap& map = *route.map;
    const ExactDistance nearest(map.surface());
    try {
        route.directions = std::make_shared<HarmonicDirections>(
            body, [&](const Vec3& x) { return image_of_nearest(map, nearest, x); }, route.centre);
    } catch (const std::exception& e) {
        log << "  no harmonic extension of the sphere map's directions (" << e.what() << ")\n";
        return false;
    }
    log << fmt::format(
        "  the sphere map's directions extended harmonically outside the body ({} iterations, "
        "{:.2f} s)\n",
        route.directions->iterations(), lap());
    return true;
}

bool add_interior_potential(const ImplicitFunction& body, double depth, WallRoute& route,
                            std::ostream& log) {
    Lap lap;
    ExteriorPotentialOptions o;
    o.source_centre = route.centre;
    o.source_radius = 0.9 * depth;
    std::shared_ptr<ExteriorPotential> potential;
    try {
        potential = std::make_shared<ExteriorPotential>(body, o);
    } catch (const std::exception& e) {
        log << "  no interior potential (" << e.what() << "): lines straight to the core\n";
        return false;
    }
    const double solve = lap();
    // The highest: the lines follow the potential as far in as they can.
    for (int tenth = 9; tenth >= 1 && route.far_level == 0; --tenth)
        if (star_shaped(Negated(*potential), -0.1 * tenth, route.centre, potential->spacing() / 2,
                        80))
            route.far_level = 0.1 * tenth;
    log << fmt::format("  interior potential ({} unknowns, {} iterations, {:.2f} s)",
                       potential->unknowns(), potential->iterations(), solve);
    if (route.far_level == 0) {
        log << fmt::format(
            ": no level of it is star-shaped around the centre ({:.2f} s), lines straight to the "
            "core\n",
            lap());
        return false;
    }
    log << fmt::format(": level {:.1f} star-shaped around the centre ({:.2f} s)\n", route.far_level,
                       lap());
    route.potential = std::move(potential);
    return true;
}

WallPaths interior_paths(const WallRoute& route, const std::vector<Vec3>& wall,
                         int cells_per_edge) {
    return interior_paths(*route.potential, wall, route.far_level, cells_per_edge, route.centre);
}

}  // namespace hexmesh

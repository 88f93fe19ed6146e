#include "hexmesh/pipeline/build_blocks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hexmesh/pipeline/exterior_paths.h"
#include "hexmesh/pipeline/make_body.h"
#include "surface/surface_topology.h"
#include "volume/o_grid.h"
#include "volume/single_block_grid.h"
#include "volume/wall_extrusion.h"

namespace hexmesh {
namespace {

// Cells per patch edge: given, or from the target cell size and the size of the body's bounds.
int cells_per_edge(const Case& c, const Box3& bounds) {
    if (!(c.grid.cell_size > 0)) return c.grid.cells_per_edge;
    const double n = std::ceil(bounds.diagonal() / (std::sqrt(3.0) * c.grid.cell_size));
    if (!(n <= 4096)) {
        throw InputError(
            fmt::format("{}: grid.cell_size: {} gives {:.0f} cells per edge for a body "
                        "of diagonal {:.4g}; expected at most 4096",
                        c.path, c.grid.cell_size, n, bounds.diagonal()));
    }
    return std::max(2, int(n));
}

int cells_per_edge(const Case& c, const ImplicitFunction& body) {
    return cells_per_edge(c, body.bounds());
}

// Throws InputError for a surface the block structure cannot grid: several pieces, one with
// handles (its genus from V - E + F, holes capped) or one that encloses no volume; logs an
// open surface (inside and outside then come from the winding number) with its widest hole,
// and names that hole in `open_hole` when it is wider than a wall cell (the bounds' diagonal
// over sqrt 3 cells_per_edge). Returns the bounds of its triangles' points.
Box3 refuse_topology(const Case& c, const TriangleSurface& surface, std::ostream& log,
                     std::string& open_hole) {
    const SurfaceTopology t = surface_topology(surface);
    const std::string& file = c.geometry.file;
    if (t.components.size() > 1)
        throw InputError(fmt::format(
            "{}: {} separate bodies (the largest has {} triangles, the next {}): hexmesh grids one "
            "closed body; give each body its own file",
            file, t.components.size(), t.components[0].triangles, t.components[1].triangles));
    const SurfaceComponent& s = t.components.at(0);
    if (s.genus > 0)
        throw InputError(fmt::format(
            "{}: genus {}: the surface has {} handle{} (V - E + F = {}{}); hexmesh grids bodies "
            "without holes through them",
            file, s.genus, s.genus, s.genus > 1 ? "s" : "", s.euler,
            s.boundary_loops > 0 ? fmt::format(", {} holes in the surface", s.boundary_loops)
                                 : ""));
    // The enclosed volume is about zero for a flat or doubled sheet, which has no inside to
    // grid (its interior grid would be cells of no volume). Taken from the centre of the
    // bounds, so that a body far from the origin keeps its digits.
    const double volume = signed_volume(surface, s.bounds.center());
    const double size = s.bounds.diagonal();
    if (s.boundary_edges == 0 && !(std::abs(volume) > 1e-9 * size * size * size))
        throw InputError(
            fmt::format("{}: the surface encloses no volume ({:.3g}, the body {:.3g} "
                        "across): a flat or doubled sheet; hexmesh grids solid bodies",
                        file, std::abs(volume), size));
    if (s.boundary_edges > 0) {
        // A hole leaves u = 0 open (the distance to the triangles does not vanish across it, and
        // its sign jumps there): wall nodes there gather on its rim. A crack is bridged; a
        // wider hole folds the wall, and a refusal of the wall or the grid then names it when
        // it spans more than a wall cell.
        const double h = size / (std::sqrt(3.0) * cells_per_edge(c, s.bounds));
        const std::string widest = fmt::format(
            "{:.3g} across ({:.1f} wall cells) around ({:.4g}, {:.4g}, {:.4g})", s.widest_hole,
            s.widest_hole / h, s.widest_hole_at.x(), s.widest_hole_at.y(), s.widest_hole_at.z());
        log << fmt::format(
            "  the surface is open: {} boundary edges around {} hole{}, the widest {}; inside "
            "and outside come from the winding number\n",
            s.boundary_edges, s.boundary_loops, s.boundary_loops > 1 ? "s" : "", widest);
        if (s.widest_hole > h)
            open_hole = fmt::format(
                "{} is open: a hole {}; close it (a crack is bridged, a wider hole folds the wall)",
                file, widest);
    }
    return s.bounds;
}

// The exterior O-grid of the case (see build_grid).
BlockGrid build_o_grid(const Case& c, const ImplicitFunction& body,
                       const std::vector<Vec3>* wall_from, const WallRoute* route) {
    OGridOptions o;
    o.cells_per_edge = cells_per_edge(c, body);
    o.layers = c.grid.wall_cells;
    o.wall_layers = wall_layers(c);
    o.far_field =
        c.far_field.shape == FarFieldShape::box ? FarFieldShape::box : FarFieldShape::sphere;
    const Vec3 centre = c.grid.center.value_or(body.bounds().center());
    o.far_field_size = c.far_field.size > 0
                           ? c.far_field.size
                           : 10 * (body.bounds().hi - centre)
                                      .cwiseAbs()
                                      .cwiseMax((body.bounds().lo - centre).cwiseAbs())
                                      .norm();
    o.centre = c.grid.center;
    if (route && !route->radial()) {
        // The lines from the wall nodes as they are now: up the potential's gradient.
        const std::vector<Vec3> wall =
            wall_from ? std::vector<Vec3>(wall_from->begin(),
                                          wall_from->begin() + Id(route->wall->size()))
                      : *route->wall;
        const WallPaths paths = exterior_paths(*route, wall, o.cells_per_edge);
        o.paths = &paths;
        return make_o_grid(body, o);
    }
    o.wall_from = wall_from;
    return make_o_grid(body, o);
}

// Throws InputError for a body (its bounds) too small, too large or too far from the origin
// for the grid's arithmetic, or a first layer too thin for it: under 1e-9 across, the
// boundary layer's edges come near 1e-15, which the quality measures (Verdict) take for
// zero-length; beyond 1e36 from the origin, products of lengths overflow (a sphere of radius
// 1e80 gives faces of negative volume); farther than 1e9 times its size, or a first layer
// under 1e-12 of it, and its coordinates keep too few digits for its cells.
void refuse_scale(const Case& c, const Box3& bounds) {
    const std::string& what = c.geometry.file.empty() ? c.path : c.geometry.file;
    const double size = bounds.diagonal();
    const double far = std::max(bounds.lo.cwiseAbs().maxCoeff(), bounds.hi.cwiseAbs().maxCoeff());
    if (!(far <= 1e36))
        throw InputError(
            fmt::format("{}: the body reaches {:.3g} from the origin; hexmesh grids "
                        "bodies within 1e36 of it: give it in larger units",
                        what, far));
    if (!(size >= 1e-9))
        throw InputError(
            fmt::format("{}: the body is {:.3g} across; hexmesh grids bodies at "
                        "least 1e-9 across: give it in smaller units",
                        what, size));
    if (!(far <= 1e9 * size))
        throw InputError(
            fmt::format("{}: the body, {:.3g} across, lies {:.3g} from the origin, "
                        "more than 1e9 times its size: its coordinates keep too few "
                        "digits for its cells; move it nearer the origin",
                        what, size, far));
    if (c.boundary_layer && !(c.boundary_layer->first_height >= 1e-12 * size))
        throw InputError(fmt::format(
            "{}: boundary_layer.first_height {:.3g}{} is under 1e-12 of the body's size ({:.3g}): "
            "its coordinates keep too few digits for such a layer",
            c.path, c.boundary_layer->first_height,
            c.boundary_layer->y_plus > 0 ? " (from y_plus)" : "", size));
}

// The body of the case, its reference surface refused if the block structure cannot grid it
// or the arithmetic cannot hold it.
void read_body(Job& job) {
    job.surface = reference_surface(job.settings.geometry, &job.log);
    if (job.surface)
        refuse_scale(job.settings,
                     refuse_topology(job.settings, *job.surface, job.log, job.open_hole));
    job.body = make_body(job.settings.geometry);
    if (!job.surface) refuse_scale(job.settings, job.body->bounds());
    job.timer.done("geometry");
}

// The wall's route and the case's open choices, resolved once (see build_blocks).
void resolve_case(Job& job) {
    Case& c = job.settings;
    const ImplicitFunction& body = *job.body;
    if (c.domain == Domain::exterior && c.grid.cell_size > 0 && !c.grid.wall_cells_given)
        c.grid.wall_cells = 2 * cells_per_edge(c, body);
    if (c.domain == Domain::exterior || c.grid.topology == Topology::o_h) {
        job.route = choose_wall_route(c, body, job.surface, cells_per_edge(c, body),
                                      job.solver_options(), job.log);
        c.grid.center = job.route.centre;
        if (!job.route.radial()) job.timer.done("wall", "(sphere map)");
    }
    if (!job.route.radial() && c.domain != Domain::exterior)
        c.grid.axis = GridAxis::none;  // one core block
    if (c.domain != Domain::exterior && c.grid.topology == Topology::o_h &&
        c.grid.axis == GridAxis::automatic) {
        const int axis = choose_o_h_axis(body, o_h_grid_options(c, body));
        c.grid.axis = axis < 0 ? GridAxis::none : GridAxis(int(GridAxis::x) + axis);
        if (axis >= 0)
            job.log << "  grid axis " << name_of(c.grid.axis)
                    << ": the body's creases run around it\n";
    }
    if (c.domain != Domain::exterior && c.grid.topology == Topology::o_h && job.route.radial() &&
        job.route.not_star_shaped.empty() && !c.grid.core_size_given) {
        const double fitted = core_size_within_wall(body, o_h_grid_options(c, body));
        if (fitted < c.grid.core_size)
            job.log << fmt::format(
                "  core_size {:.3g}: the default {} would reach the wall near the "
                "centre\n",
                fitted, c.grid.core_size);
        c.grid.core_size = fitted;
    }
}

// Logs the wall-normal lines where the body is too thin for the whole boundary layer.
void log_thin_wall_lines(const BlockGrid& grid, const WallLayers& law, std::ostream& log) {
    const ThinWallLines thin = thin_wall_lines(grid, law);
    if (thin.cut == 0) return;
    log << fmt::format(
        "  the body is thin for the boundary layer's {} layers ({:.4g} thick) on {} of {} wall "
        "lines: they take fewer layers of the same first height, down to {} on a line {:.4g} "
        "long from the wall at ({:.4g}, {:.4g}, {:.4g})\n",
        law.layers, layers_thickness(law), thin.cut, thin.lines, thin.fewest, thin.length,
        thin.wall.x(), thin.wall.y(), thin.wall.z());
}

}  // namespace

WallLayers wall_layers(const Case& c) {
    if (!c.boundary_layer) return {};
    return {c.boundary_layer->first_height, c.boundary_layer->growth_ratio,
            c.boundary_layer->layers};
}

OHGridOptions o_h_grid_options(const Case& c, const ImplicitFunction& body) {
    OHGridOptions o;
    o.cells_per_edge = cells_per_edge(c, body);
    o.wall_cells = c.grid.wall_cells;
    o.core_size = c.grid.core_size;
    o.wall_layers = wall_layers(c);
    o.centre = c.grid.center;
    o.axis = axis_index(c.grid.axis);
    o.ring_cells = c.grid.ring_cells;
    o.frame_cells = c.grid.frame_cells;
    return o;
}

BlockGrid build_grid(const Case& c, const ImplicitFunction& body,
                     const std::vector<Vec3>* wall_from, const WallRoute* route) {
    if (c.domain == Domain::exterior) return build_o_grid(c, body, wall_from, route);
    if (c.grid.topology == Topology::single_block) {
        if (wall_from)
            throw std::invalid_argument("a single block is not built from a given wall grid");
        SingleBlockOptions o;
        o.cells = c.grid.cells;
        o.wall_layers = wall_layers(c);
        o.centre = c.grid.center;
        return make_single_block_grid(body, o);
    }
    OHGridOptions o = o_h_grid_options(c, body);
    o.wall_from = wall_from;
    if (route && !route->radial()) {
        o.axis = -1;
        o.centre = route->centre;
        o.core_half = route->core_half;
        if (!wall_from) o.wall_nodes = route->wall.get();
        if (route->potential)  // in along the interior potential's gradient lines
            o.paths = [&](const std::vector<Vec3>& wall) {
                return interior_paths(*route, wall, o.cells_per_edge);
            };
        return make_o_h_grid(body, o);
    }
    if (c.grid.axis == GridAxis::automatic) o.axis = choose_o_h_axis(body, o);
    return make_o_h_grid(body, o);
}

void build_blocks(Job& job) {
    read_body(job);
    resolve_case(job);
    const Case& c = job.settings;
    const WallRoute& route = job.route;
    try {
        job.levels.clear();
        job.levels.push_back(build_grid(c, *job.body, nullptr, &route));
    } catch (const std::invalid_argument& e) {
        if (!route.not_star_shaped.empty())
            throw InputError(job.naming_hole(
                fmt::format("{}: {}, and the rays from there do not place a wall: {}", c.path,
                            route.not_star_shaped, e.what())));
        if (!route.radial())
            throw InputError(job.naming_hole(fmt::format("{}: {}", c.path, e.what())));
        throw std::invalid_argument(job.naming_hole(e.what()));
    }
    // A single block's lines run from wall to wall, each half cut on its own: not logged.
    if (c.domain == Domain::exterior || c.grid.topology != Topology::single_block)
        log_thin_wall_lines(job.grid(), wall_layers(c), job.log);
    job.timer.done("grid",
                   fmt::format("({}, {} blocks, {} cells)",
                               c.domain == Domain::exterior ? "o-grid" : name_of(c.grid.topology),
                               job.grid().blocks.size(), job.grid().num_cells()));
}

}  // namespace hexmesh

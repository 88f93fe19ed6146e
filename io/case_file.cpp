#include "io/case_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/export_grid.h"
#include "io/json_fields.h"

namespace hexmesh {
namespace {

using nlohmann::json;

constexpr long long max_cells = 200'000'000;  // beyond this a run would not fit in memory

GeometrySpec parse_geometry(const json& value, const std::string& file, const std::string& path);

std::vector<GeometrySpec> parse_operands(const JsonFields& g, const char* op,
                                         const std::string& file) {
    const json& list = g.at(op);
    if (!list.is_array() || list.size() < 2) g.fail(op, "an array of at least 2 shapes");
    std::vector<GeometrySpec> children;
    for (size_t m = 0; m < list.size(); ++m)
        children.push_back(parse_geometry(list[m], file, fmt::format("{}[{}]", g.path_of(op), m)));
    return children;
}

void parse_primitive(const JsonFields& p, GeometrySpec& s) {
    const Vec3 zero = Vec3::Zero();
    if (s.kind == BodyKind::sphere) {
        p.allow_only({"center", "radius"});
        s.radius = p.required_positive_number("radius");
    } else if (s.kind == BodyKind::ellipsoid) {
        p.allow_only({"center", "semi_axes"});
        if (!p.has("semi_axes")) p.fail("semi_axes", "an array of 3 positive numbers");
        s.semi_axes = p.positive_vec3("semi_axes", zero);
    } else if (s.kind == BodyKind::box) {
        p.allow_only({"center", "size"});
        if (!p.has("size")) p.fail("size", "an array of 3 positive numbers");
        s.size = p.positive_vec3("size", zero);
    } else if (s.kind == BodyKind::cylinder) {
        p.allow_only({"center", "radius", "height"});
        s.radius = p.required_positive_number("radius");
        s.height = p.required_positive_number("height");
    } else if (s.kind == BodyKind::torus) {
        p.allow_only({"center", "major_radius", "minor_radius"});
        s.major_radius = p.required_positive_number("major_radius");
        s.minor_radius = p.required_positive_number("minor_radius");
        if (s.minor_radius >= s.major_radius)
            p.fail("minor_radius", fmt::format("a number below major_radius ({})", s.major_radius));
    } else {  // cone
        p.allow_only({"center", "bottom_radius", "top_radius", "height"});
        s.bottom_radius = p.required_positive_number("bottom_radius");
        s.top_radius = p.number("top_radius", 0);
        if (s.top_radius < 0) p.fail("top_radius", "a number >= 0");
        s.height = p.required_positive_number("height");
    }
    s.center = p.vec3("center", zero);
}

// {"file": "part.stl", "voxel_size": 0.01, "feature_angle": 30}, {"points": "cloud.ply"},
// {"sections": "stack.txt"}: a path relative to the case file's folder, under the key s.kind.
void parse_surface_file(const JsonFields& g, const std::string& file, GeometrySpec& s) {
    const json& name = g.at(name_of(s.kind));
    if (!name.is_string() || name.get<std::string>().empty())
        g.fail(name_of(s.kind),
               s.kind == BodyKind::file     ? "a surface file name (.stl, .obj, .off or .ply)"
               : s.kind == BodyKind::points ? "a point cloud file name (.ply or .xyz)"
                                            : "a cross-section file name");
    const std::filesystem::path relative(name.get<std::string>());
    s.file =
        relative.is_absolute()
            ? relative.string()
            : (std::filesystem::path(file).parent_path() / relative).lexically_normal().string();
    s.voxel_size = g.positive_number("voxel_size", 0);
    s.feature_angle = g.number("feature_angle", s.feature_angle);
    if (!(s.feature_angle > 0 && s.feature_angle <= 180))
        g.fail("feature_angle", "an angle in (0, 180] degrees (180: no sharp creases)");
}

GeometrySpec parse_geometry(const json& value, const std::string& file, const std::string& path) {
    const JsonFields g(value, file, path);
    g.allow_only({"sphere", "ellipsoid", "box", "cylinder", "torus", "cone", "file", "points",
                  "sections", "voxel_size", "feature_angle", "union", "intersection", "difference",
                  "translate", "rotate", "scale"});
    GeometrySpec s;
    int shapes = 0;
    for (std::size_t k = 0; k < body_kind_names.size(); ++k)
        if (g.has(body_kind_names[k])) s.kind = BodyKind(k), ++shapes;
    if (shapes != 1) {
        throw InputError(fmt::format(
            "{}: {}: expected exactly one shape (sphere, ellipsoid, box, cylinder, torus, cone, "
            "file, points, sections, union, intersection, difference), got {}",
            file, path, shapes));
    }
    if (g.has("voxel_size") && s.kind != BodyKind::file)
        g.fail("voxel_size", "no voxel size: it goes with \"file\"");
    if (g.has("feature_angle") && s.kind != BodyKind::file)
        g.fail("feature_angle", "no feature angle: it goes with \"file\"");
    if (is_csg(s.kind))
        s.children = parse_operands(g, name_of(s.kind), file);
    else if (is_file_body(s.kind))
        parse_surface_file(g, file, s);
    else
        parse_primitive(g.object(name_of(s.kind)), s);

    s.translate = g.vec3("translate", Vec3::Zero());
    s.scale = g.positive_number("scale", 1.0);
    if (g.has("rotate")) {
        const JsonFields r = g.object("rotate");
        r.allow_only({"axis", "degrees"});
        if (!r.has("axis")) r.fail("axis", "an array of 3 numbers, not all zero");
        s.rotate_axis = r.vec3("axis", Vec3::UnitZ());
        if (!(s.rotate_axis.norm() > 0)) r.fail("axis", "an array of 3 numbers, not all zero");
        if (!r.has("degrees")) r.fail("degrees", "a finite number");
        s.rotate_degrees = r.number("degrees", 0);
    }
    return s;
}

// `exterior`: the lines run from the wall to the far field, 10 body radii out by default, so
// wall_cells defaults to twice cells_per_edge (build_blocks resolves it again when cell_size sets
// cells_per_edge).
GridSpec parse_grid(const JsonFields& g, bool exterior) {
    g.allow_only({"topology", "cells_per_edge", "cell_size", "wall_cells", "core_size", "cells",
                  "center", "axis", "ring_cells", "frame_cells"});
    GridSpec grid;
    grid.topology = g.choice("topology", grid.topology, topology_names);
    grid.cells_per_edge = g.integer("cells_per_edge", grid.cells_per_edge, 2, 4096);
    if (g.has("cell_size") && g.has("cells_per_edge"))
        g.fail("cell_size", "either cells_per_edge or cell_size, not both");
    grid.cell_size = g.positive_number("cell_size", 0);
    grid.wall_cells_given = g.has("wall_cells");
    grid.wall_cells =
        g.integer("wall_cells", exterior ? 2 * grid.cells_per_edge : grid.wall_cells, 1, 4096);
    grid.core_size_given = g.has("core_size");
    grid.core_size = g.number("core_size", grid.core_size);
    if (!(grid.core_size > 0 && grid.core_size < 1)) g.fail("core_size", "a number in (0, 1)");
    if (g.has("cells")) {
        const json& c = g.at("cells");
        if (!c.is_array() || c.size() != 3) g.fail("cells", "an array of 3 integers in [2, 4096]");
        for (int d = 0; d < 3; ++d) {
            if (!c[d].is_number_integer() || c[d].get<long long>() < 2 ||
                c[d].get<long long>() > 4096)
                g.fail("cells", "an array of 3 integers in [2, 4096]");
            grid.cells[d] = c[d].get<int>();
        }
    }
    if (g.has("center")) grid.center = g.vec3("center", Vec3::Zero());
    grid.axis = g.choice("axis", grid.axis, axis_names);
    grid.ring_cells = g.integer("ring_cells", grid.ring_cells, 0, 4096);
    grid.frame_cells = g.integer("frame_cells", grid.frame_cells, 0, 4096);
    const bool axial = grid.axis != GridAxis::none;
    const bool explicit_axis = axial && grid.axis != GridAxis::automatic;
    if (!axial && g.has("ring_cells")) g.fail("ring_cells", "given with an \"axis\" only");
    if (!axial && g.has("frame_cells")) g.fail("frame_cells", "given with an \"axis\" only");
    if ((explicit_axis || g.has("frame_cells")) && !(grid.cell_size > 0) &&
        2 * grid.frame_cells >= grid.cells_per_edge)
        g.fail("frame_cells", "under half of cells_per_edge");
    if (grid.topology != Topology::o_h && explicit_axis)
        g.fail("axis", "\"none\" or \"auto\" (an axis goes with topology o-h)");
    // The cells of the grid asked for: with an explicit axis the axial core (column m x m,
    // m = n - 2 frame, rings r x m, frame) and its end patches; "auto" is counted as one core
    // block, which it stays unless the body has round creases around an axis.
    const long long n = grid.cells_per_edge, m = std::max(1LL, n - 2LL * grid.frame_cells),
                    r = grid.ring_cells > 0 ? grid.ring_cells : (n + 1) / 2;
    const long long total =
        grid.topology != Topology::o_h ? (long long)grid.cells[0] * grid.cells[1] * grid.cells[2]
        : !explicit_axis               ? n * n * n + 6 * n * n * grid.wall_cells
                         : n * (n * n + 4 * r * m) + (6 * n * n + 8 * r * m) * grid.wall_cells;
    if (total > max_cells) {
        g.fail(grid.topology == Topology::o_h ? "cells_per_edge" : "cells",
               fmt::format("a grid of at most {} cells (this one has {})", max_cells, total));
    }
    return grid;
}

// {"y_plus": 1, "velocity": U, "density": rho, "viscosity": mu, "length": L or "reynolds": Re}
void parse_y_plus(const JsonFields& b, BoundaryLayerSpec& bl) {
    if (b.has("first_height")) b.fail("y_plus", "either first_height or y_plus, not both");
    bl.y_plus = b.required_positive_number("y_plus");
    const double velocity = b.required_positive_number("velocity");
    const double density = b.required_positive_number("density");
    const double viscosity = b.required_positive_number("viscosity");
    if (b.has("length") == b.has("reynolds"))
        b.fail("length",
               "the reference length of the Reynolds number, or \"reynolds\" (one of them)");
    bl.reynolds = b.has("reynolds")
                      ? b.required_positive_number("reynolds")
                      : density * velocity * b.required_positive_number("length") / viscosity;
    bl.first_height =
        first_height_from_y_plus(bl.y_plus, bl.reynolds, velocity, density, viscosity);
}

BoundaryLayerSpec parse_boundary_layer(const JsonFields& b, const GridSpec& grid) {
    b.allow_only({"first_height", "growth_ratio", "layers", "y_plus", "velocity", "density",
                  "viscosity", "length", "reynolds"});
    BoundaryLayerSpec bl;
    if (b.has("y_plus"))
        parse_y_plus(b, bl);
    else
        bl.first_height = b.required_positive_number("first_height");
    bl.growth_ratio = b.number("growth_ratio", 1.2);
    if (!(bl.growth_ratio >= 1 && bl.growth_ratio <= 3))
        b.fail("growth_ratio", "a number in [1, 3]");
    const int available = grid.topology == Topology::o_h
                              ? grid.wall_cells - 1
                              : std::min({grid.cells[0], grid.cells[1], grid.cells[2]}) / 2 - 1;
    if (!b.has("layers")) b.fail("layers", "an integer number of layers");
    if (available < 1) b.fail("layers", "no layers: the grid leaves no room for a boundary layer");
    bl.layers = b.integer("layers", 0, 1, available);
    return bl;
}

SolverSpec parse_solver(const JsonFields& s) {
    s.allow_only({"untangle", "optimize", "theta", "max_iterations", "optimize_iterations",
                  "surface_iterations", "wall_fidelity"});
    SolverSpec solver;
    const auto methods = {"explicit", "block-diagonal", "coordinate-split", "newton-cg", "lbfgs"};
    solver.untangle = s.choice("untangle", solver.untangle, methods);
    solver.optimize = s.choice("optimize", solver.optimize, methods);
    solver.theta = s.number("theta", solver.theta);
    if (!(solver.theta > 0 && solver.theta < 1)) s.fail("theta", "a number in (0, 1)");
    solver.max_iterations = s.integer("max_iterations", solver.max_iterations, 1, 1000000);
    solver.optimize_iterations =
        s.integer("optimize_iterations", solver.optimize_iterations, 0, 1000000);
    solver.surface_iterations =
        s.integer("surface_iterations", solver.surface_iterations, 0, 1000000);
    solver.wall_fidelity = s.number("wall_fidelity", solver.wall_fidelity);
    if (!(solver.wall_fidelity >= 0 && solver.wall_fidelity <= 1e6))
        s.fail("wall_fidelity", "a number from 0 to 1e6");
    return solver;
}

FarFieldSpec parse_far_field(const JsonFields& f) {
    f.allow_only({"shape", "size"});
    FarFieldSpec far;
    far.shape = f.choice("shape", far.shape, far_field_shape_names);
    far.size = f.positive_number("size", 0);
    return far;
}

FlowSpec parse_flow(const JsonFields& f) {
    f.allow_only({"velocity", "density", "viscosity", "turbulence", "turbulence_intensity",
                  "turbulence_length"});
    FlowSpec flow;
    flow.velocity = f.vec3("velocity", flow.velocity);
    if (!(flow.velocity.norm() > 0)) f.fail("velocity", "a non-zero vector [ux, uy, uz]");
    flow.density = f.positive_number("density", flow.density);
    flow.viscosity = f.positive_number("viscosity", flow.viscosity);
    flow.turbulence = f.choice("turbulence", flow.turbulence, {"laminar", "k-omega-sst"});
    flow.turbulence_intensity =
        f.positive_number("turbulence_intensity", flow.turbulence_intensity);
    flow.turbulence_length = f.positive_number("turbulence_length", 0);
    return flow;
}

TetMeshSpec parse_tet_mesh(const JsonFields& f) {
    f.allow_only({"cell_size", "wall_cell_size", "grading", "facet_distance", "feature_angle"});
    TetMeshSpec t;
    t.cell_size = f.positive_number("cell_size", 0);
    t.wall_cell_size = f.positive_number("wall_cell_size", 0);
    t.grading = f.positive_number("grading", t.grading);
    t.facet_distance = f.positive_number("facet_distance", 0);
    t.feature_angle = f.number("feature_angle", t.feature_angle);
    if (!(t.feature_angle > 0 && t.feature_angle < 180))
        f.fail("feature_angle", "an angle in (0, 180) degrees");
    if (t.cell_size > 0 && t.wall_cell_size > t.cell_size)
        f.fail("wall_cell_size", "a size at most cell_size (" + std::to_string(t.cell_size) + ")");
    return t;
}

std::vector<std::string> parse_outputs(const JsonFields& top, const std::string& file) {
    const json& list = top.at("outputs");
    if (!list.is_array())
        top.fail("outputs", "an array of format names (" + export_format_list() + ")");
    std::vector<std::string> outputs;
    for (size_t m = 0; m < list.size(); ++m) {
        if (!list[m].is_string() || !is_export_format(list[m].get<std::string>())) {
            // "(vtk)" kept first: tests/io/test_case_file.cpp matches that wording.
            throw InputError(
                fmt::format("{}: outputs[{}]: expected a format name (vtk), got {}; "
                            "the formats are {}",
                            file, m, describe(list[m]), export_format_list()));
        }
        outputs.push_back(list[m].get<std::string>());
    }
    return outputs;
}

json vec3_json(const Vec3& v) {
    return json::array({v.x(), v.y(), v.z()});
}

json geometry_json(const GeometrySpec& s) {
    json g;
    if (is_csg(s.kind)) {
        json children = json::array();
        for (const GeometrySpec& child : s.children) children.push_back(geometry_json(child));
        g[name_of(s.kind)] = children;
    } else if (is_file_body(s.kind)) {
        g[name_of(s.kind)] = std::filesystem::absolute(s.file).lexically_normal().string();
        if (s.voxel_size > 0) g["voxel_size"] = s.voxel_size;
        if (s.kind == BodyKind::file) g["feature_angle"] = s.feature_angle;
    } else {
        json p = {{"center", vec3_json(s.center)}};
        if (s.kind == BodyKind::sphere) p["radius"] = s.radius;
        if (s.kind == BodyKind::ellipsoid) p["semi_axes"] = vec3_json(s.semi_axes);
        if (s.kind == BodyKind::box) p["size"] = vec3_json(s.size);
        if (s.kind == BodyKind::cylinder) p["radius"] = s.radius, p["height"] = s.height;
        if (s.kind == BodyKind::torus)
            p["major_radius"] = s.major_radius, p["minor_radius"] = s.minor_radius;
        if (s.kind == BodyKind::cone) {
            p["bottom_radius"] = s.bottom_radius;
            p["top_radius"] = s.top_radius;
            p["height"] = s.height;
        }
        g[name_of(s.kind)] = p;
    }
    if (s.translate != Vec3::Zero()) g["translate"] = vec3_json(s.translate);
    if (s.scale != 1) g["scale"] = s.scale;
    if (s.rotate_degrees != 0)
        g["rotate"] = {{"axis", vec3_json(s.rotate_axis)}, {"degrees", s.rotate_degrees}};
    return g;
}

}  // namespace

std::string case_to_json(const Case& c) {
    json root;
    root["geometry"] = geometry_json(c.geometry);
    root["domain"] = name_of(c.domain);
    json grid = {{"topology", name_of(c.grid.topology)},
                 {"wall_cells", c.grid.wall_cells},
                 {"core_size", c.grid.core_size},
                 {"cells", c.grid.cells}};
    if (c.grid.cell_size > 0)
        grid["cell_size"] = c.grid.cell_size;
    else
        grid["cells_per_edge"] = c.grid.cells_per_edge;
    if (c.grid.center) grid["center"] = vec3_json(*c.grid.center);
    grid["axis"] = name_of(c.grid.axis);
    if (c.grid.axis != GridAxis::none && c.grid.ring_cells > 0)
        grid["ring_cells"] = c.grid.ring_cells;
    if (c.grid.axis != GridAxis::none) grid["frame_cells"] = c.grid.frame_cells;
    root["grid"] = grid;
    if (c.domain == Domain::exterior) {
        root["far_field"] = {{"shape", name_of(c.far_field.shape)}};
        if (c.far_field.size > 0) root["far_field"]["size"] = c.far_field.size;
    }
    if (c.boundary_layer)
        root["boundary_layer"] = {{"first_height", c.boundary_layer->first_height},
                                  {"growth_ratio", c.boundary_layer->growth_ratio},
                                  {"layers", c.boundary_layer->layers}};
    root["flow"] = {{"velocity", vec3_json(c.flow.velocity)},
                    {"density", c.flow.density},
                    {"viscosity", c.flow.viscosity},
                    {"turbulence", c.flow.turbulence}};
    if (c.flow.turbulence != "laminar") {
        root["flow"]["turbulence_intensity"] = c.flow.turbulence_intensity;
        if (c.flow.turbulence_length > 0)
            root["flow"]["turbulence_length"] = c.flow.turbulence_length;
    }
    root["solver"] = {{"untangle", c.solver.untangle},
                      {"optimize", c.solver.optimize},
                      {"theta", c.solver.theta},
                      {"max_iterations", c.solver.max_iterations},
                      {"optimize_iterations", c.solver.optimize_iterations},
                      {"surface_iterations", c.solver.surface_iterations},
                      {"wall_fidelity", c.solver.wall_fidelity}};
    return root.dump(2) + "\n";
}

double first_height_from_y_plus(double y_plus, double reynolds, double velocity, double density,
                                double viscosity) {
    const double cf = 0.026 / std::pow(reynolds, 1.0 / 7.0);
    const double u_tau = std::sqrt(0.5 * cf * velocity * velocity);
    return y_plus * viscosity / (density * u_tau);
}

Case parse_case(const std::string& text, const std::string& path) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        const auto at = what.find("parse error");
        if (at != std::string::npos) what = what.substr(at);
        throw InputError(fmt::format("{}: malformed JSON: {}", path, what));
    }
    const JsonFields top(root, path, "");
    top.allow_only({"geometry", "domain", "grid", "far_field", "boundary_layer", "solver",
                    "outputs", "refinement", "tet_mesh", "flow"});
    Case c;
    c.path = path;
    if (!top.has("geometry")) top.fail("geometry", "an object describing the body");
    c.geometry = parse_geometry(top.at("geometry"), path, "geometry");
    c.domain = top.choice("domain", c.domain, domain_names);
    static const json no_grid = json::object();
    c.grid = parse_grid(top.has("grid") ? top.object("grid") : JsonFields(no_grid, path, "grid"),
                        c.domain == Domain::exterior);
    if (c.domain == Domain::exterior && c.grid.axis != GridAxis::none &&
        c.grid.axis != GridAxis::automatic)
        top.object("grid").fail(
            "axis", "\"none\" or \"auto\" (an exterior domain is gridded by the O-grid)");
    if (c.domain == Domain::exterior && c.grid.topology != Topology::o_h)
        top.fail("grid.topology",
                 "\"o-h\" (an exterior domain is gridded by the O-grid of its "
                 "six wall patches)");
    if (top.has("far_field")) {
        if (c.domain != Domain::exterior)
            top.fail("far_field", "no far_field: it goes with \"domain\": \"exterior\"");
        c.far_field = parse_far_field(top.object("far_field"));
    }
    if (top.has("boundary_layer"))
        c.boundary_layer = parse_boundary_layer(top.object("boundary_layer"), c.grid);
    if (top.has("solver")) c.solver = parse_solver(top.object("solver"));
    if (top.has("outputs")) c.outputs = parse_outputs(top, path);
    if (top.has("refinement")) {
        const JsonFields r = top.object("refinement");
        r.allow_only({"levels"});
        c.refinement.levels = r.integer("levels", c.refinement.levels, 1, 5);
    }
    if (top.has("tet_mesh")) c.tet_mesh = parse_tet_mesh(top.object("tet_mesh"));
    if (top.has("flow")) c.flow = parse_flow(top.object("flow"));
    return c;
}

Case read_case(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw InputError(fmt::format("{}: cannot open case file ({})", path, std::strerror(errno)));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(fmt::format("{}: cannot read case file", path));
    return parse_case(text.str(), path);
}

}  // namespace hexmesh

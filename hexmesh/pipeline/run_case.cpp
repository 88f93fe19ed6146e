#include "hexmesh/pipeline/run_case.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/mend_cells.h"
#include "hexmesh/pipeline/optimize_grid.h"
#include "hexmesh/pipeline/optimize_surface.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/refine_family.h"
#include "hexmesh/pipeline/wall_route.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/export_grid.h"
#include "io/report_page.h"
#include "io/staged_output.h"
#include "io/vtk_mesh.h"
#include "surface/surface_topology.h"
#include "volume/feature_snapping.h"
#include "volume/grid_meter.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"
#include "volume/single_block_grid.h"
#include "volume/tfi.h"

namespace hexmesh {
namespace {

untangle::UntangleOptions untangle_options(const SolverSpec& s, std::ostream& log) {
    untangle::UntangleOptions o;
    o.untangle_solver.method = untangle::method_from_name(s.untangle);
    o.optimize_solver.method = untangle::method_from_name(s.optimize);
    o.theta = s.theta;
    o.max_untangle_iterations = s.max_iterations;
    o.max_optimize_iterations = s.optimize_iterations;
    o.log = &log;
    return o;
}

// Cells per patch edge: given, or from the target cell size and the body's size.
int cells_per_edge(const Case& c, const ImplicitFunction& body) {
    if (!(c.grid.cell_size > 0)) return c.grid.cells_per_edge;
    const double n = std::ceil(body.bounds().diagonal() / (std::sqrt(3.0) * c.grid.cell_size));
    if (!(n <= 4096)) {
        throw InputError(
            fmt::format("{}: grid.cell_size: {} gives {:.0f} cells per edge for a body "
                        "of diagonal {:.4g}; expected at most 4096",
                        c.path, c.grid.cell_size, n, body.bounds().diagonal()));
    }
    return std::max(2, int(n));
}

// Throws InputError for a surface the block structure cannot grid: several pieces, or one with
// handles (its genus from V - E + F, holes capped); logs an open surface (inside and outside
// then come from the winding number).
void refuse_topology(const Case& c, const TriangleSurface& surface, std::ostream& log) {
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
    if (s.boundary_edges > 0)
        log << fmt::format(
            "  the surface is open: {} boundary edges around {} holes; inside and "
            "outside come from the winding number\n",
            s.boundary_edges, s.boundary_loops);
}

// What makes the grid invalid, for the refusal: its inverted cells, else what a finite-volume
// solver refuses in it.
std::string invalid_cells(const QualityReport& q) {
    if (q.inverted_cells > 0) return fmt::format("{} inverted cells", q.inverted_cells);
    std::vector<std::string> what;
    if (q.negative_pyramids > 0)
        what.push_back(fmt::format("{} face pyramids of negative volume", q.negative_pyramids));
    if (q.faces_over_90_deg > 0)
        what.push_back(fmt::format("{} faces at 90 degrees of non-orthogonality or more",
                                   q.faces_over_90_deg));
    if (q.nonpositive_volumes > 0)
        what.push_back(fmt::format("{} cells of volume <= 0", q.nonpositive_volumes));
    return fmt::format("cells that a finite-volume solver refuses: {}", fmt::join(what, ", "));
}

// Throws (nothing written) when the grid is not valid for a solver (QualityReport::solver_valid:
// inverted cells, cells turned inside out at their centre or faces warped past it), unless
// keep_invalid.
void refuse_invalid(const Case& c, const GridReport& report, const std::string& dir,
                    const RunOptions& options) {
    if (!report.quality.solver_valid() && !options.keep_invalid) {
        const Vec3& at = report.quality.worst_cell_centre;
        const std::optional<CellPlace>& w = report.worst_cell;
        throw std::runtime_error(fmt::format(
            "{}: the grid {}has {} (min scaled Jacobian {:.3g} at ({:.4g}, {:.4g}, {:.4g}){}); "
            "nothing written (use --keep-invalid to write it as grid_invalid.*)",
            c.path, dir.empty() ? "" : "of " + dir.substr(0, dir.size() - 1) + " ",
            invalid_cells(report.quality), report.quality.min_scaled_jacobian, at.x(), at.y(),
            at.z(),
            w ? fmt::format(", block {} cell ({}, {}, {}){}", w->block, w->i, w->j, w->k,
                            w->on_wall ? " on the wall" : "")
              : ""));
    }
}

// Writes one grid, its quality.json and grid.case.json into `out` under `dir` ("" or
// "level_2/"), refusing a grid with inverted cells unless keep_invalid.
void write_level(const Case& c, const BlockGrid& grid, GridReport report, const std::string& dir,
                 const RunOptions& options, PhaseTimer& timer, StagedOutput& out) {
    refuse_invalid(c, report, dir, options);
    const std::string stem = dir + (report.quality.solver_valid() ? "grid" : "grid_invalid");
    const std::string file = out.path(stem + (grid.blocks.size() == 1 ? ".vts" : ".vtm"));
    std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    write_vtk_grid(grid, file);
    for (const std::string& format : c.outputs)  // the VTK grid above is always written
        if (format != "vtk")
            write_grid_format(
                grid, format,
                out.path(dir + export_file_name(format, stem.substr(dir.size()), grid)), c.flow);
    timer.done(dir.empty() ? "write" : "write " + dir.substr(0, dir.size() - 1));
    report.phase_seconds = timer.phases();
    out.write_text(dir + "quality.json", quality_json(report));
    out.write_text(dir + "grid.case.json", case_to_json(c));
    if (!options.report) return;
    ReportPage page =
        grid_report_page(fmt::format("hexmesh run {}{}", c.path,
                                     dir.empty() ? "" : ", " + dir.substr(0, dir.size() - 1)),
                         report, draw_grid(grid), case_to_json(c));
    page.peak_memory_bytes = peak_memory();
    out.write_text(dir + "report.html", report_page_html(page));
    timer.done(dir.empty() ? "report" : "report " + dir.substr(0, dir.size() - 1));
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
    o.axis = c.grid.axis == "none" || c.grid.axis == "auto" ? -1 : c.grid.axis[0] - 'x';
    o.ring_cells = c.grid.ring_cells;
    o.frame_cells = c.grid.frame_cells;
    return o;
}

BlockGrid build_grid(const Case& c, const ImplicitFunction& body,
                     const std::vector<Vec3>* wall_from, const WallRoute* route) {
    if (c.domain == "exterior") {
        OGridOptions o;
        o.cells_per_edge = cells_per_edge(c, body);
        o.layers = c.grid.wall_cells;
        o.wall_layers = wall_layers(c);
        o.far_field = c.far_field.shape == "box" ? FarFieldShape::box : FarFieldShape::sphere;
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
    if (c.grid.topology == "single-block") {
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
        return make_o_h_grid(body, o);
    }
    if (c.grid.axis == "auto") o.axis = choose_o_h_axis(body, o);
    return make_o_h_grid(body, o);
}

namespace {

// Cells whose scaled Jacobian (corners and centre) is <= 0.
Id nonpositive_cells(const BlockGrid& grid) {
    const std::vector<double> sj = scaled_jacobians(grid);
    return Id(std::count_if(sj.begin(), sj.end(), [](double q) { return !(q > 0); }));
}

// The surface pass (hexmesh/pipeline/optimize_surface.h), then the volume from the optimized
// wall: the O-H and O-grid lines built again, a single block's interior carried along by
// TFI. When the volume built so has more cells with a scaled Jacobian <= 0 than the grid
// had, or cannot be built (wall nodes that slid far from their lines' core or far-field
// ends, in deep concavities), the grid as constructed is kept.
void surface_pass(const Case& c, const ImplicitFunction& body, const WallRoute* route,
                  BlockGrid& grid, std::ostream& log) {
    untangle::UntangleOptions surface = untangle_options(c.solver, log);
    surface.max_optimize_iterations = c.solver.surface_iterations;
    log << "  surface grid on u = 0 (2D functional, wall nodes only):\n";
    const std::vector<Vec3> built = grid.points;
    const Id bad_before = nonpositive_cells(grid);
    const SurfaceOptimizationResult s = optimize_wall_surface(grid, body, surface);
    log << untangle::format_untangle_summary(s.solve)
        << fmt::format("  {} wall nodes, {} corner triangles; largest move {:.3g} wall edges\n",
                       s.nodes, s.triangles, s.max_move);
    if (c.domain == "exterior" || c.grid.topology != "single-block") {
        try {
            BlockGrid rebuilt =
                build_grid(c, body, &grid.points, route);  // same blocks and node ids
            grid.points = std::move(rebuilt.points);
        } catch (const std::invalid_argument& e) {  // a wall node behind its core node
            log << "  no volume can be built from that wall (" << e.what()
                << "): the grid as constructed is kept\n";
            grid.points = built;
            return;
        }
    } else {
        for (const Block& block : grid.blocks) carry_interior_tfi(block, built, grid.points);
    }
    const Id bad_after = nonpositive_cells(grid);
    if (bad_after > bad_before) {
        log << fmt::format(
            "  the volume built from that wall has {} cells with a scaled Jacobian <= 0, "
            "against {} as constructed: the grid as constructed is kept\n",
            bad_after, bad_before);
        grid.points = built;
    }
}

// The cells a solver refuses mended node by node (hexmesh/pipeline/mend_cells.h), one line
// to `log`; the cells still refused.
Id mend(BlockGrid& grid, const ImplicitFunction& body, std::ostream& log) {
    const MendResult m = mend_refused_cells(grid, body);
    log << fmt::format(
        "  cells a solver refuses mended node by node (the solver's own checks): {} -> {}, "
        "smallest margin {:.3g} -> {:.3g} ({} moves)\n",
        m.refused_before, m.refused_after, m.min_margin_before, m.min_margin_after, m.moves);
    return m.refused_after;
}

// The worst cells optimized again in their neighbourhood (optimize_grid.h,
// polish_worst_cells), the wall and its boundary layer held. While the grid then has cells a
// solver refuses: they are mended node by node (mend); what is left, with 2, 4, then 8 rings
// around them, layers free (validity before the layers' spacing); then every cell under the
// threshold, layers free; then mended again. One line per pass.
void polish(const Case& c, const ImplicitFunction& body, BlockGrid& grid, std::ostream& log) {
    // Cells the joint untangling left inverted are not repaired by a local optimization (it
    // runs the same continuation): the grid goes to its refusal as it is.
    if (const Id inverted = measure_quality(grid).inverted_cells; inverted > 0) {
        log << fmt::format("  no polish: {} cells are still inverted\n", inverted);
        return;
    }
    PolishOptions o;
    o.untangle = untangle_options(c.solver, log);
    o.untangle.log = nullptr;              // a summary line instead
    o.untangle.optimize_tolerance = 1e-7;  // a small problem: its worst cells weigh
    o.untangle.max_optimize_iterations = 50;
    const int layers = wall_layers(c).layers;
    if (layers > 0) o.held = wall_layer_nodes(grid, layers);
    for (int pass = 0; pass < 5; ++pass) {
        const PolishResult r = polish_worst_cells(grid, body, o);
        if (r.cells > 0) {
            if (o.refused_only)
                log << fmt::format(
                    "  cells a solver refuses (checkMesh's cell checks) and {} rings around them, "
                    "layers free: {} -> {}",
                    o.rings, r.refused_before, r.refused_after);
            else
                log << fmt::format(
                    "  worst cells polished{}: {} -> {} cells with a scaled Jacobian under {}",
                    o.held.empty() ? ", layers free" : " beyond the boundary layer", r.cells,
                    r.cells_after, o.below);
            log << fmt::format(", min scaled Jacobian {:.3g} -> {:.3g} ({} rounds, {:.2f} s)\n",
                               r.min_sj_before, r.min_sj_after, r.rounds, r.seconds);
        }
        if (r.refused_after == 0) return;
        // A face warped past its cell's centre, which the corner tets do not see: the nodes of
        // such cells moved one by one, before the layers around them are let go.
        if (pass == 0 && mend(grid, body, log) == 0) return;
        o.held.clear();
        o.refused_only = pass < 3;  // rings 2, 4, 8; then every cell under the threshold, rings 2
        o.rings = pass < 3 ? 2 << pass : 2;
    }
    mend(grid, body, log);
}

}  // namespace

RunResult run_case(const Case& given, const std::string& outdir, const RunOptions& options,
                   std::ostream& log) {
    PhaseTimer timer(log);
    StagedOutput out(outdir);  // the folder locked from the start: a second run into it is refused
    const std::optional<TriangleSurface> surface = reference_surface(given.geometry);
    if (surface) refuse_topology(given, *surface, log);
    const Body body = make_body(given.geometry);
    timer.done("geometry");
    Case c = given;  // with the wall's route and grid.axis "auto" resolved, once, and written so
    if (c.domain == "exterior" && c.grid.cell_size > 0 && !c.grid.wall_cells_given)
        c.grid.wall_cells = 2 * cells_per_edge(c, *body);
    WallRoute route;
    if (c.domain == "exterior" || c.grid.topology == "o-h") {
        route = choose_wall_route(c, *body, surface, cells_per_edge(c, *body),
                                  untangle_options(c.solver, log), log);
        c.grid.center = route.centre;
        if (!route.radial()) timer.done("wall (sphere map)");
    }
    if (!route.radial() && c.domain != "exterior") c.grid.axis = "none";  // one core block
    if (c.domain != "exterior" && c.grid.topology == "o-h" && c.grid.axis == "auto") {
        const int axis = choose_o_h_axis(*body, o_h_grid_options(c, *body));
        c.grid.axis = axis < 0 ? "none" : std::string(1, char('x' + axis));
        if (axis >= 0)
            log << "  grid axis " << c.grid.axis << ": the body's creases run around it\n";
    }
    if (c.domain != "exterior" && c.grid.topology == "o-h" && route.radial() &&
        route.not_star_shaped.empty() && !c.grid.core_size_given) {
        const double fitted = core_size_within_wall(*body, o_h_grid_options(c, *body));
        if (fitted < c.grid.core_size)
            log << fmt::format(
                "  core_size {:.3g}: the default {} would reach the wall near the "
                "centre\n",
                fitted, c.grid.core_size);
        c.grid.core_size = fitted;
    }
    RunResult result;
    try {
        result.grid = build_grid(c, *body, nullptr, &route);
    } catch (const std::invalid_argument& e) {
        if (!route.not_star_shaped.empty())
            throw InputError(fmt::format("{}: {}, and the rays from there do not place a wall: {}",
                                         c.path, route.not_star_shaped, e.what()));
        if (!route.radial()) throw InputError(fmt::format("{}: {}", c.path, e.what()));
        throw;
    }
    timer.done("grid", fmt::format("({}, {} blocks, {} cells)",
                                   c.domain == "exterior" ? "o-grid" : c.grid.topology,
                                   result.grid.blocks.size(), result.grid.num_cells()));
    if (c.solver.optimize_iterations > 0 || measure_quality(result.grid).inverted_cells > 0) {
        // A wall placed through the sphere map follows no crease: nodes pulled onto creases
        // across its lines would fold its quads. It slides on u = 0 as a smooth surface.
        if (route.radial()) {
            const FeatureSnapping snapped = snap_to_features(result.grid, *body);
            if (snapped.crease_nodes + snapped.corner_nodes > 0)
                log << fmt::format("  sharp features: {} wall nodes on creases, {} on corners\n",
                                   snapped.crease_nodes, snapped.corner_nodes);
        }
        if (c.solver.surface_iterations > 0) {
            surface_pass(c, *body, &route, result.grid, log);
            timer.done("surface");
        }
        GridOptimizationOptions o;
        o.untangle = untangle_options(c.solver, log);
        o.wall_layers = wall_layers(c);
        o.keep_crease_shapes = c.domain == "exterior";  // its lines leave creases mitred
        const GridOptimizationResult r = optimize_grid(result.grid, *body, o);
        log << untangle::format_untangle_summary(r.solve);
        if (r.layers_skipped) {
            log << fmt::format(
                "  boundary layer not laid again: the joint optimization left {} inverted "
                "elements, some away "
                "from the wall and its layers\n",
                r.solve.inverted_after);
        } else if (o.wall_layers.layers > 0 && r.laid_nodes == 0) {
            log << "  boundary layer kept as built (no wall-normal line can be laid alone)\n";
        } else if (r.layers_blocked > 0) {
            log << fmt::format(
                "  boundary layer laid along the wall normals crosses the grid ({} corner tets "
                "inverted between held nodes): the joint optimization's grid is kept\n",
                r.layers_blocked);
        } else if (o.wall_layers.layers > 0) {
            log << "  boundary layer laid along the wall normals"
                << (r.lines_given_back > 0 ? fmt::format(" (but on {} wall lines, whose laid cells "
                                                         "would cross or fall under half "
                                                         "the worst scaled Jacobian before: they "
                                                         "keep the joint optimization's)",
                                                         r.lines_given_back)
                                           : std::string())
                << ", rest optimized again:\n"
                << untangle::format_untangle_summary(r.layers_held);
            if (!r.layers_laid)
                log << "  the laid layers left inverted cells: the joint optimization's grid is "
                       "kept\n";
        }
        timer.done("optimization");
        polish(c, *body, result.grid, log);
        timer.done("polish");
    }
    result.report = measure_grid(result.grid, *body, wall_layers(c), surface ? &*surface : nullptr);
    timer.done("quality");

    if (c.refinement.levels == 1) {
        write_level(c, result.grid, result.report, "", options, timer, out);
        result.report.phase_seconds = timer.phases();
        result.files = out.commit();
        return result;
    }
    refuse_invalid(c, result.report, "level_1/", options);  // before refining it
    result.level_reports.push_back(result.report);
    std::vector<BlockGrid> grids = {result.grid};
    // The polish of refined levels keeps its own theta (RefinementOptions, volume-weighted): it
    // holds the interpolated wall spacing, which a shape-weighted polish lets drift.
    const RefinementOptions refinement;
    for (int level = 2; level <= c.refinement.levels; ++level) {
        RefinementResult r = refine_on_body(grids.back(), *body, refinement);
        timer.done(
            fmt::format("refinement level {}", level),
            fmt::format("({} cells, {} wall nodes projected)", r.grid.num_cells(), r.projected));
        const WallLayers law = refined_wall_layers(wall_layers(c), level);
        result.level_reports.push_back(
            measure_grid(r.grid, *body, law, surface ? &*surface : nullptr));
        timer.done(fmt::format("quality level {}", level));
        grids.push_back(std::move(r.grid));
    }
    std::vector<FamilyLevel> table;
    for (int level = 1; level <= c.refinement.levels; ++level) {
        const std::string dir = fmt::format("level_{}/", level);
        write_level(c, grids[level - 1], result.level_reports[level - 1], dir, options, timer, out);
        table.push_back(family_level(level, result.level_reports[level - 1]));
    }
    out.write_text("family.json", family_json(table));
    result.files = out.commit();
    result.grid = std::move(grids.back());
    result.report = result.level_reports.back();
    return result;
}

}  // namespace hexmesh

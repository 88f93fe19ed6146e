#include "hexmesh/pipeline/run_case.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/pipeline/surface_grid.h"
#include "hexmesh/pipeline/untangle_and_optimize.h"
#include "hexmesh/pipeline/wall_route.h"
#include "hexmesh/pipeline/write.h"
#include "hexmesh/quality/block_quality.h"
#include "io/staged_output.h"

namespace hexmesh {
namespace {

// Whether the grid measured `after` is better than the one measured `before`: valid for a
// solver where that one is not; both valid, with a higher worst scaled Jacobian; neither, with
// fewer inverted cells.
bool better_grid(const QualityReport& after, const QualityReport& before) {
    if (after.solver_valid() != before.solver_valid()) return after.solver_valid();
    if (after.solver_valid()) return after.min_scaled_jacobian > before.min_scaled_jacobian;
    return after.inverted_cells < before.inverted_cells;
}

// What the log says of a grid measured `q`: the cells a solver refuses, or its worst cell, and
// that of the grid measured `other` when both are valid.
std::string grid_state(const QualityReport& q, const QualityReport* other = nullptr) {
    if (!q.solver_valid()) return invalid_cells(q);
    std::string s = fmt::format("worst scaled Jacobian {:.4f}", q.min_scaled_jacobian);
    if (other && other->solver_valid())
        s += fmt::format(" against {:.4f}", other->min_scaled_jacobian);
    return s;
}

// Makes the grid again along job.route as it now is (blocks, surface pass, optimization; the
// timer's "grid" phase noted `phase`) and keeps it when it is the better grid (better_grid) of
// the two, the one it replaces measured `before`. Else that grid and `before_route` are put
// back and false is returned. The log says which is kept: "<made>: <its state>; it is kept", or
// "...; <kept_grid> is kept".
bool make_again_and_keep_better(Job& job, const QualityReport& before, WallRoute before_route,
                                const std::string& phase, const std::string& made,
                                const std::string& kept_grid) {
    BlockGrid kept = std::move(job.grid());
    std::vector<WallQuality::Stage> kept_misses = job.wall_misses;
    const bool kept_untangled = job.untangled;
    const double kept_work = job.untangling_work;
    job.grid() = build_grid(job.settings, *job.body, nullptr, &job.route);
    job.timer.done("grid", phase);
    make_surface_grid(job);
    untangle_and_optimize(job);
    const QualityReport after = measure_quality(job.grid());
    if (better_grid(after, before)) {
        job.log << fmt::format("  {}: {}; it is kept\n", made, grid_state(after, &before));
        return true;
    }
    job.log << fmt::format("  {}: {}; {} is kept\n", made, grid_state(after, &before), kept_grid);
    job.grid() = std::move(kept);
    job.wall_misses = std::move(kept_misses);
    job.untangled = kept_untangled;
    job.untangling_work = kept_work;
    job.route = std::move(before_route);
    return false;
}

// When the first grid is valid, the second's untangling (both passes together) is given at most
// this many times the first grid's untangling work: the second grid is then made only to be
// compared. It ends the hand's second grid inside, invalid either way, at 7 inverted elements
// (the run 40 -> 24 s); the U's second grid, the better one (0.1008 against 0.0842), takes
// 1.65 times the first's work, homer's at 157 216 cells (0.0602 against 0.0445) less than it.
constexpr double second_grid_work = 2;

// Inside, every corner tet weighs the same while the volume grid is untangled, as outside: on
// the shared bodies the bull and homer come out with min scaled Jacobian 0.35 and 0.23 instead
// of 0.13 and 0.08, the hand and the spool valid at the first try instead of after two more
// (bench/RESULTS.md, "Interior grids untangled with equal weights first"). On other bodies each
// tet weighing its target's volume (the small cells of the boundary layer keeping their shapes)
// gives the better grid: valid where the other keeps cells a solver refuses (two of eight random
// bodies with limbs; a third along its straight lines), or with a better worst cell (the U:
// 0.10 against 0.08; a random body 0.30 against 0.09). Which one a route needs is not known
// beforehand, so the grid is made again along the same route with the other weighting, and the
// better of the two kept (better_grid). Run once per route: after the first grid, and after the
// straight lines when their grid is kept. Not when the grid had nothing to untangle: the weights
// count only while untangling, and the grid would come out the same. A valid first grid bounds
// the second's untangling work (second_grid_work).
void retry_with_other_weights(Job& job) {
    if (job.settings.domain == Domain::exterior || !job.untangled) return;
    const QualityReport before = measure_quality(job.grid());
    const bool volume = !job.volume_weights;
    // A weighting (volume weights or not), in full and in short.
    const auto how = [](bool v) {
        return v ? "each tet weighing its target's volume" : "every tet weighing the same";
    };
    const auto name = [](bool v) { return std::string(v ? "volume weights" : "equal weights"); };
    job.log << fmt::format("  the grid untangled with {}: {}; the grid again, {}\n", how(!volume),
                           grid_state(before), how(volume));
    if (before.solver_valid()) {
        job.work_budget = second_grid_work * std::max(job.untangling_work, 1.0);
        job.log << fmt::format(
            "  (the first grid is valid: the second's untangling gets a work budget of {:.0f}, "
            "{} times the first's)\n",
            job.work_budget, second_grid_work);
    }
    job.volume_weights = volume;
    if (!make_again_and_keep_better(job, before, job.route, "(" + name(volume) + ")",
                                    "untangled with " + name(volume),
                                    "the grid untangled with " + name(!volume)))
        job.volume_weights = !volume;
    job.work_budget = 0;
}

// Untangled and optimized, the interior grid of a body that is not star-shaped, its lines in
// along the interior potential's gradient lines, may keep cells a solver refuses where the
// straight lines from the wall to the core would not (which of the two a body takes is not
// known beforehand). Then the grid is made again with its lines straight to the core, and the
// better of the two kept: the valid one, or the one with fewer inverted cells. Returns whether
// the grid with straight lines is kept.
bool retry_with_straight_lines(Job& job) {
    WallRoute& route = job.route;
    if (job.settings.domain == Domain::exterior || route.radial() || !route.potential) return false;
    const QualityReport along = measure_quality(job.grid());
    if (along.solver_valid()) return false;
    job.log << fmt::format(
        "  the lines along the interior potential left {}: the grid again, its lines straight "
        "to the core\n",
        invalid_cells(along));
    WallRoute kept_route = route;
    route.potential.reset();
    route.far_level = 0;
    return make_again_and_keep_better(
        job, along, std::move(kept_route), "(lines straight to the core)",
        "the lines straight to the core", "the grid with lines along the interior potential");
}

// The exterior grid of a body that is not star-shaped, its lines out along the exterior
// potential's gradient lines, keeps inverted cells where neighbouring gradient lines part at a
// saddle of the potential (between legs, fingers, arms), building a cell with no width that the
// optimizer cannot open. Then the grid is made again with its lines along the fibres of the
// sphere map's directions extended harmonically (add_directions), which do not part there, and
// the better of the two kept. A valid grid is not made again: the fibres cross the potential's
// levels at an angle, and where both grids are valid the gradient lines' cells are the better
// (the U outside: mean scaled Jacobian 0.917 against 0.845).
void retry_with_fibres(Job& job) {
    const Case& c = job.settings;
    WallRoute& route = job.route;
    if (c.domain != Domain::exterior || !route.along_first_lines()) return;
    const QualityReport along = measure_quality(job.grid());
    if (along.solver_valid()) return;
    job.log << fmt::format(
        "  the gradient lines left {}: the grid again, its lines along the fibres of the sphere "
        "map's directions\n",
        invalid_cells(along));
    WallRoute kept_route = route;
    const bool added = add_directions(*job.body, route, job.log);
    job.timer.done("wall", "(directions)");
    if (!added) return;
    make_again_and_keep_better(job, along, std::move(kept_route), "(lines along fibres)",
                               "the lines along fibres", "the grid along the gradient lines");
}

// The exterior grid of a body that is not star-shaped, its lines out along the exterior
// potential's gradient lines or fibres, keeps inverted cells where neighbouring lines part round a
// limb or fold onto one another (the optimizer cannot open a cell that was built with no width).
// Then the grid is made again with its lines carried out level by level, repaired on the levels
// where they part or fold (spread_on_levels), and the better of the two kept. A grid that was valid
// is not made again: the repairs move lines that were sound as well.
void retry_with_spread_levels(Job& job) {
    const Case& c = job.settings;
    WallRoute& route = job.route;
    if (c.domain != Domain::exterior || route.radial() || route.spread_on_levels) return;
    const QualityReport along = measure_quality(job.grid());
    if (along.solver_valid()) return;
    const std::string lines = route.directions ? "the lines along fibres" : "the gradient lines";
    const std::string grid =
        route.directions ? "the grid along fibres" : "the grid along the gradient lines";
    job.log << fmt::format(
        "  {} left {}: their nodes carried out level by level and spread out where they part or "
        "fold\n",
        lines, invalid_cells(along));
    WallRoute kept_route = route;
    route.spread_on_levels = true;
    LevelSpreading done;
    exterior_paths(route, *route.wall, o_h_grid_options(c, *job.body).cells_per_edge, &done);
    job.timer.done("levels", "(lines spread out)");
    job.log << fmt::format("  {} levels, spread out on {} ({} of {} lines moved){}\n", done.levels,
                           done.levels_spread, done.lines_moved, route.wall->size(),
                           done.levels_left > 0
                               ? fmt::format("; on {} no repair left the folded or squeezed "
                                             "quads sound: left as they were",
                                             done.levels_left)
                               : "");
    if (done.lines_moved == 0) {
        job.log << "  no line moved: " << grid << " stands\n";
        route = std::move(kept_route);
        return;
    }
    make_again_and_keep_better(job, along, std::move(kept_route), "(lines spread on levels)",
                               "the lines spread on levels", grid);
}

}  // namespace

RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log) {
    Job job(c, options, log);
    StagedOutput out(outdir);  // the folder locked from the start: a second run into it is refused
    build_blocks(job);
    if (c.solver.optimize_iterations > 0 || measure_quality(job.grid()).inverted_cells > 0) {
        make_surface_grid(job);
        untangle_and_optimize(job);
        retry_with_other_weights(job);
        if (retry_with_straight_lines(job)) retry_with_other_weights(job);
        retry_with_fibres(job);
        retry_with_spread_levels(job);
    }
    measure(job);
    refine_levels(job);
    RunResult result;
    result.files = write_grids(job, out);
    if (job.levels.size() > 1) result.level_reports = job.reports;
    result.report = job.reports.back();
    if (job.levels.size() == 1) result.report.phase_seconds = job.timer.phases();
    result.report.peak_memory_bytes = peak_memory();
    result.grid = std::move(job.levels.back());
    return result;
}

}  // namespace hexmesh

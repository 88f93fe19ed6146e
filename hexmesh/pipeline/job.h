// Job: what the stages of `run` hand on to each other — the case, its body, the grids, their
// reports, the log and the phase timer. The stages, in the order run_case.h runs them:
// build_blocks.h, surface_grid.h, untangle_and_optimize.h (on the problem of corner_tets.h,
// with the layer pass of lay_boundary_layer.h), measure.h, refine.h, write.h.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/wall_route.h"
#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"
#include "surface/body.h"
#include "untangle/untangle.h"

namespace hexmesh {

struct RunOptions {
    // A grid with inverted cells is refused (std::runtime_error, nothing written) unless
    // keep_invalid is set: then it is written as grid_invalid.* so no one takes it for valid.
    bool keep_invalid = false;
    // Writes report.html beside each grid's quality.json (report_page_html: pictures,
    // histograms, worst cells, settings, time and memory).
    bool report = true;
};

// The untangler's options of a case's solver block (methods, theta, iteration budgets), its
// progress lines to `log` (none if null).
inline untangle::UntangleOptions case_solver_options(const SolverSpec& s, std::ostream* log) {
    untangle::UntangleOptions o;
    o.untangle_solver.method = untangle::method_from_name(s.untangle);
    o.optimize_solver.method = untangle::method_from_name(s.optimize);
    o.theta = s.theta;
    o.max_untangle_iterations = s.max_iterations;
    o.max_optimize_iterations = s.optimize_iterations;
    o.log = log;
    return o;
}

struct Job {
    Job(const Case& c, const RunOptions& o, std::ostream& l)
        : settings(c), options(o), log(l), timer(l) {}

    // The case as given, its open choices (grid centre, axis, core size, exterior wall
    // cells) resolved by build_blocks, once, and written so in grid.case.json.
    Case settings;
    RunOptions options;
    std::ostream& log;  // one line per phase (timer) and the solvers' progress
    PhaseTimer timer;
    std::optional<TriangleSurface> surface;  // the surface file's triangles, if any
    Body body;                               // the implicit body u
    WallRoute route;                         // how the wall grid is placed on it
    // The corner tets weigh their targets' volumes while the volume grid is untangled, instead
    // of each the same: inside, for the grid made again with the other weighting (run_case.cpp,
    // retry_with_other_weights).
    bool volume_weights = false;
    // The volume passes of the grid found inverted corner tets to untangle (the joint pass, or
    // the layer pass whose layers the grid keeps), so the weights above counted.
    bool untangled = false;
    // The work of those untanglings (GridOptimizationResult::untangling_work), and, when > 0,
    // the budget of the volume passes' untangling of the grid being made (UntangleOptions::
    // max_work, shared by both passes): for a grid made again only to be compared with a valid
    // one (run_case.cpp).
    double untangling_work = 0;
    double work_budget = 0;
    // A hole of the surface wider than a wall cell, named at the end of the refusals that its
    // folds can cause (the wall not placed, the grid invalid); empty for a closed surface.
    std::string open_hole;
    // The nested family: levels[0] is the grid the stages build and optimize, each next one
    // refine_on_body of the one before (settings.refinement.levels in all); reports[l] measures
    // levels[l].
    std::vector<BlockGrid> levels;
    std::vector<GridReport> reports;
    // How far the wall of levels[0] missed the body at the stages that made it (note_wall_miss),
    // for a surface file: measure puts them into reports[0].
    std::vector<WallQuality::Stage> wall_misses;

    // `message`, with open_hole after it when there is one: a refusal of the wall or the grid.
    std::string naming_hole(const std::string& message) const {
        return open_hole.empty() ? message : message + "; " + open_hole;
    }

    BlockGrid& grid() { return levels.front(); }  // level 1, the grid the stages optimize

    // The untangler's options of the case's solver block, logging to `log`.
    untangle::UntangleOptions solver_options() const {
        return case_solver_options(settings.solver, &log);
    }
};

}  // namespace hexmesh

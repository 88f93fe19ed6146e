// The `run` job: case file in, grid files and quality report out — the stages of job.h, composed.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/job.h"
#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"

namespace hexmesh {

struct RunResult {
    BlockGrid grid;     // the finest level written
    GridReport report;  // its report
    // With "refinement": {"levels": N > 1}, the report of each level, level 1 first.
    std::vector<GridReport> level_reports;
    std::vector<std::string> files;  // written outputs, final paths
};

// Builds the grid, measures it and writes OUTDIR/grid.vtm (grid.vts for one block),
// OUTDIR/quality.json, OUTDIR/grid.case.json (case_to_json: the geometry `hexmesh refine`
// projects new wall nodes onto) and OUTDIR/report.html, all or nothing. With c.refinement.levels =
// N > 1, the grid is level 1 of a nested family: OUTDIR/level_1 ... OUTDIR/level_N each hold those
// three files, level L + 1 being refine_on_body of level L (its wall law refined_wall_layers), and
// OUTDIR/family.json the study table. grid.axis "auto" is resolved once (choose_o_h_axis)
// and written so in grid.case.json. Progress goes to `log`, one line per phase.
// The stages: build_blocks, then (unless optimize_iterations is 0 and no cell is inverted)
// make_surface_grid and untangle_and_optimize, measure, refine_levels, write_grids.
RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log);

}  // namespace hexmesh

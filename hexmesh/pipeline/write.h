// The last `run` stage, write: each grid of the job with its quality.json, grid.case.json and
// report.html, in the formats the case asks for, all or nothing (io/staged_output.h).
#pragma once

#include <string>
#include <vector>

#include "hexmesh/pipeline/job.h"
#include "io/staged_output.h"

namespace hexmesh {

// Writes the job's grid into `out` as OUTDIR/grid.vtm (grid.vts for one block) with its
// quality.json, grid.case.json (case_to_json: the geometry `hexmesh refine` projects new wall
// nodes onto), report.html (unless job.options.report is off) and every format of the case's
// outputs; with several levels, OUTDIR/level_1 ... level_N each hold those files and
// OUTDIR/family.json the study table. A grid a solver refuses is refused (refuse_invalid)
// unless keep_invalid: then written as grid_invalid.*. Commits `out` and returns the final
// paths of the files written.
std::vector<std::string> write_grids(Job& job, StagedOutput& out);

}  // namespace hexmesh

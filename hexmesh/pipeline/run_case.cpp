#include "hexmesh/pipeline/run_case.h"

#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/pipeline/surface_grid.h"
#include "hexmesh/pipeline/untangle_and_optimize.h"
#include "hexmesh/pipeline/write.h"
#include "hexmesh/quality/block_quality.h"
#include "io/staged_output.h"

namespace hexmesh {

RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log) {
    Job job(c, options, log);
    StagedOutput out(outdir);  // the folder locked from the start: a second run into it is refused
    build_blocks(job);
    if (c.solver.optimize_iterations > 0 || measure_quality(job.grid()).inverted_cells > 0) {
        make_surface_grid(job);
        untangle_and_optimize(job);
    }
    measure(job);
    refine_levels(job);
    RunResult result;
    result.files = write_grids(job, out);
    if (job.levels.size() > 1) result.level_reports = job.reports;
    result.report = job.reports.back();
    if (job.levels.size() == 1) result.report.phase_seconds = job.timer.phases();
    result.grid = std::move(job.levels.back());
    return result;
}

}  // namespace hexmesh

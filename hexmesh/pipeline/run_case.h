// The `run` job: case file in, grid files and quality report out.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "io/case_file.h"
#include "io/quality_report.h"
#include "surface/body.h"

namespace hexmesh {

struct RunResult {
    BlockGrid grid;
    GridReport report;
    std::vector<std::string> files;  // written outputs, final paths
};

// The initial grid of the case's body (O-H or single block), before any optimization.
BlockGrid build_grid(const Case& c, const ImplicitFunction& body);

// Quality metrics of `grid`, plus surface fidelity against `body` over its slip nodes.
GridReport measure_grid(const BlockGrid& grid, const ImplicitFunction& body);

struct RunOptions {
    // A grid with inverted cells is refused (std::runtime_error, nothing written) unless
    // keep_invalid is set: then it is written as grid_invalid.* so no one takes it for valid.
    bool keep_invalid = false;
};

// Builds the grid, measures it and writes OUTDIR/grid.vtm (grid.vts for one block) and
// OUTDIR/quality.json, all or nothing. Progress goes to `log`, one line per phase.
RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log);

}  // namespace hexmesh

// The `run` job: case file in, grid files and quality report out.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/pipeline/wall_route.h"
#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"
#include "surface/body.h"
#include "volume/o_h_grid.h"
#include "volume/stretching.h"

namespace hexmesh {

struct RunResult {
    BlockGrid grid;     // the finest level written
    GridReport report;  // its report
    // With "refinement": {"levels": N > 1}, the report of each level, level 1 first.
    std::vector<GridReport> level_reports;
    std::vector<std::string> files;  // written outputs, final paths
};

// The initial grid of the case's body, before any optimization: interior O-H or single
// block, or the exterior O-grid out to the far field. Throws InputError when a cell_size
// asks for an absurd number of cells. With `wall_from` (the points of a grid build_grid made
// for the same case, its wall grid since moved on u = 0), the O-H and O-grid lines are built
// from those wall nodes instead of the radial projections; the single block has no such
// construction and throws std::invalid_argument. grid.axis "auto" is resolved by
// choose_o_h_axis (volume/o_h_grid.h) on each call.
// With a route that is not radial (a body that is not star-shaped: hexmesh/pipeline/wall_route.h),
// the route's wall lattice (or wall_from's) instead of the radial projections, and for the
// exterior its lines up the route's potential.
BlockGrid build_grid(const Case& c, const ImplicitFunction& body,
                     const std::vector<Vec3>* wall_from = nullptr,
                     const WallRoute* route = nullptr);

// The O-H grid options of an interior case (grid.axis "auto" as -1: see choose_o_h_axis).
OHGridOptions o_h_grid_options(const Case& c, const ImplicitFunction& body);

// The boundary-layer law of the case (layers = 0 without a boundary_layer block).
WallLayers wall_layers(const Case& c);

struct RunOptions {
    // A grid with inverted cells is refused (std::runtime_error, nothing written) unless
    // keep_invalid is set: then it is written as grid_invalid.* so no one takes it for valid.
    bool keep_invalid = false;
    // Writes report.html beside each grid's quality.json (report_page_html: pictures,
    // histograms, worst cells, settings, time and memory).
    bool report = true;
};

// Builds the grid, measures it and writes OUTDIR/grid.vtm (grid.vts for one block),
// OUTDIR/quality.json, OUTDIR/grid.case.json (case_to_json: the geometry `hexmesh refine`
// projects new wall nodes onto) and OUTDIR/report.html, all or nothing. With c.refinement.levels =
// N > 1, the grid is level 1 of a nested family: OUTDIR/level_1 ... OUTDIR/level_N each hold those
// three files, level L + 1 being refine_on_body of level L (its wall law refined_wall_layers), and
// OUTDIR/family.json the study table. grid.axis "auto" is resolved once (choose_o_h_axis)
// and written so in grid.case.json. Progress goes to `log`, one line per phase.
RunResult run_case(const Case& c, const std::string& outdir, const RunOptions& options,
                   std::ostream& log);

}  // namespace hexmesh

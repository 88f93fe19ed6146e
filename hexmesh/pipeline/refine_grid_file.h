// The `refine` job: a block grid file in, a grid one or more levels finer out, its last level
// refined, measured and written block by block so that memory never holds it whole.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"

namespace hexmesh {

struct RefineFileOptions {
    int levels = 1;      // how many times every cell is split into 8
    bool report = true;  // write report.html (pictures, histograms, worst cells)
    // Export formats besides VTK (export_format_list but vtk), named as export_file_name
    // names them ("grid"): with several processes "openfoam" is a decomposed case, one
    // processor folder per process, and the others are written from the level gathered
    // whole at rank 0 (write_refined_formats).
    std::vector<std::string> formats;
};

struct RefineFileResult {
    GridReport report;               // of the finest level
    std::vector<std::string> files;  // written outputs, final paths
};

// Reads the block grid at `grid_path` (VTK, from `run`), refines it options.levels times on the
// body of `c` (refine_on_body, then refine_blocks for the last level: each fine block measured,
// drawn and written as it is made, then dropped) and writes OUTDIR/grid.vtm (grid.vts for one
// block), quality.json, grid.case.json and report.html, all or nothing. Throws
// std::runtime_error, nothing written, when the refined grid has inverted cells. Progress goes
// to `log`: one line per phase and per fine block.
RefineFileResult refine_grid_file(const std::string& grid_path, const Case& c,
                                  const std::string& outdir, const RefineFileOptions& options,
                                  std::ostream& log);

}  // namespace hexmesh

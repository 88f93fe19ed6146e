// The `run` stage measure: the quality report of the job's grid against its body
// (cells, faces, wall layers, surface fidelity; refine_levels measures the finer levels with
// measure_level), and the refusal of a grid a solver cannot take.
#pragma once

#include <string>

#include "hexmesh/pipeline/job.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"

namespace hexmesh {

// job.reports = {the report of job.grid()} against the body, the case's boundary-layer law and
// the surface file (the Hausdorff distance), if any, with job.wall_misses.
void measure(Job& job);

// For a job with a surface file: how far job.grid()'s wall now misses it (the report's surface
// to wall in wall cells, max and 99th percentile) added to job.wall_misses as `stage`. Nothing
// is added when the wall has no quad of non-zero area.
void note_wall_miss(Job& job, const std::string& stage);

// The report of job.levels[level - 1] (a refined level: the wall law refined_wall_layers).
GridReport measure_level(const Job& job, int level);

// What makes a grid invalid, for messages: "N inverted cells", else what a finite-volume
// solver refuses in it ("cells that a finite-volume solver refuses: ...").
std::string invalid_cells(const QualityReport& q);

// Throws std::runtime_error (nothing written) when `report`'s grid is not valid for a solver
// (QualityReport::solver_valid: inverted cells, cells turned inside out at their centre or faces
// warped past it), unless job.options.keep_invalid; `dir` ("" or "level_2/") names the level.
void refuse_invalid(const Job& job, const GridReport& report, const std::string& dir);

}  // namespace hexmesh

// The quality report of a block grid (cells, wall layers, surface fidelity, phases): the table
// printed to the terminal and quality.json.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/wall_quality.h"

namespace hexmesh {

// Where a cell of a block grid is: its block, its (i, j, k) there, and whether a face of it
// lies on the wall.
struct CellPlace {
    std::string block;
    int i = 0, j = 0, k = 0;
    bool on_wall = false;
};

struct GridReport {
    QualityReport quality;
    // Where quality.worst_cell is, for a block grid.
    std::optional<CellPlace> worst_cell;
    // Where each of quality.worst_cells is (the same order), for a block grid.
    std::vector<CellPlace> worst_places;
    // Surface fidelity: max |u| over wall nodes divided by the length scale h (the mean
    // wall-edge length), when the grid was built from a known body.
    std::optional<double> max_surface_distance;
    std::optional<double> length_scale;
    // Boundary-layer metrics and, for grids of a surface file, the Hausdorff distance.
    std::optional<WallQuality> wall;
    // Wall-clock seconds per pipeline phase, in the order they ran (a phase run again, as a
    // retry's "grid" or "optimization", once more).
    std::vector<std::pair<std::string, double>> phase_seconds;
    // The run's peak resident memory, bytes, when measured.
    std::optional<double> peak_memory_bytes;
};

// A grid of a surface file follows the body when every vertex of the surface lies within this
// many sizes of its nearest wall quad from the grid's wall (WallQuality::surface_in_cells_max);
// beyond, the wall skips part of the body (a horn, a fin, a wing's trailing edge) or bridges
// a groove.
constexpr double follows_body_wall_cells = 0.5;

// False when the grid's wall misses part of the body as above; true when it follows it, or
// when no surface was measured (a body given by a formula).
bool follows_body(const GridReport& report);

// One line naming where the wall misses the body most and by how much; empty when it
// follows it.
std::string body_missed(const GridReport& report);

// The warning `run` and `refine` print for a grid they wrote that misses the body
// ("\nwarning: " + prefix + body_missed + ..., ending in a newline); empty when it follows it.
std::string body_missed_warning(const GridReport& report, const std::string& prefix = "");

// One line naming how many wall cells lie through the wall (WallQuality::cells_through_wall),
// the thinnest and where; empty when there are none or the wall was not measured.
std::string through_wall(const GridReport& report);

// The warning `run` and `refine` print for a grid they wrote with wall cells through the wall
// ("\nwarning: " + prefix + through_wall + ..., ending in a newline); empty when there are none.
std::string through_wall_warning(const GridReport& report, const std::string& prefix = "");

// A note ("\nnote: ...", ending in a newline) when cells of `q` are over checkMesh's aspect-ratio
// limit, which fails checkMesh but not a solver; empty otherwise, and for a grid a solver
// refuses (a cell of volume <= 0 counts as over the limit, as in checkMesh, and the note would
// say that solvers run on it).
std::string aspect_ratio_note(const QualityReport& q);

// Aligned "name  value" lines, one per metric, ending in a newline: every first value ends
// in the same column; rows with several values (min/mean/max) continue to its right. The
// wall rows appear when `wall` is set, the "time per phase" block (each phase once, its runs
// summed, and the total) when phase_seconds is not empty, the peak memory when measured.
std::string format_quality_table(const GridReport& report);

// The same numbers as a JSON object: keys as in QualityReport, plus "valid" (for the solver),
// "follows_body" (follows_body above; null when no surface was measured), and, when
// present, "wall" (nested objects; null for a target the law did not give) and "phases"
// (name: seconds).
std::string quality_json(const GridReport& report);

}  // namespace hexmesh

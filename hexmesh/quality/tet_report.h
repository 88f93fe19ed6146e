// The quality report of tet meshes: the table printed to the terminal (meshes side by side)
// and one mesh's JSON.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hexmesh/quality/tet_quality.h"

namespace hexmesh {

// One column of a tet mesh's quality table: a mesh's report, and optionally the largest
// distance of its boundary points to the body over the cell size h, and the time it took.
struct TetQualityColumn {
    std::string name;
    const TetQualityReport* quality = nullptr;
    std::optional<double> boundary_distance;
    std::optional<double> seconds;
    std::optional<double> crease_distance;  // largest distance of a crease point to its crease, / h
};

// The metrics of TetQualityReport as rows, one column per mesh (side by side to compare).
std::string format_tet_quality_table(const std::vector<TetQualityColumn>& columns);

// One mesh's report as JSON: keys as in TetQualityReport, plus "valid" and, when given,
// "max_boundary_distance_over_h".
std::string tet_quality_json(const TetQualityReport& quality,
                             std::optional<double> boundary_distance);

}  // namespace hexmesh

// The quality report of a grid: the table printed to the terminal and quality.json.
#pragma once

#include <optional>
#include <string>

#include "hexmesh/core/quality.h"

namespace hexmesh {

struct GridReport {
    QualityReport quality;
    // Surface fidelity: max |u| over wall nodes divided by the length scale h (the mean
    // wall-edge length), when the grid was built from a known body.
    std::optional<double> max_surface_distance;
    std::optional<double> length_scale;
};

// Aligned "name  value" lines, one per metric, ending in a newline.
std::string format_quality_table(const GridReport& report);

// The same numbers as a JSON object (keys as in QualityReport, plus "valid").
std::string quality_json(const GridReport& report);

}  // namespace hexmesh

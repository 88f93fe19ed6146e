#include "io/quality_report.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace hexmesh {

std::string format_quality_table(const GridReport& r) {
    const QualityReport& q = r.quality;
    std::string out;
    auto row = [&](const char* name, const std::string& value) {
        out += fmt::format("  {:<30}{:>14}\n", name, value);
    };
    row("cells", fmt::format("{}", q.cells));
    row("inverted corner tets", fmt::format("{}", q.inverted_corner_tets));
    row("inverted cells", fmt::format("{}", q.inverted_cells));
    row("min scaled Jacobian", fmt::format("{:.4f}", q.min_scaled_jacobian));
    row("mean scaled Jacobian", fmt::format("{:.4f}", q.mean_scaled_jacobian));
    row("max skewness", fmt::format("{:.4f}", q.max_skewness));
    row("max non-orthogonality (deg)", fmt::format("{:.2f}", q.max_non_orthogonality_deg));
    row("max aspect ratio", fmt::format("{:.4g}", q.max_aspect_ratio));
    row("max volume ratio", fmt::format("{:.4g}", q.max_volume_ratio));
    row("min cell volume", fmt::format("{:.4g}", q.min_volume));
    if (r.max_surface_distance)
        row("max |u| / h on the wall", fmt::format("{:.3g}", *r.max_surface_distance));
    if (r.length_scale) row("h (mean wall edge)", fmt::format("{:.4g}", *r.length_scale));
    return out;
}

std::string quality_json(const GridReport& r) {
    const QualityReport& q = r.quality;
    nlohmann::ordered_json j;
    j["valid"] = q.inverted_corner_tets == 0;
    j["cells"] = q.cells;
    j["inverted_corner_tets"] = q.inverted_corner_tets;
    j["inverted_cells"] = q.inverted_cells;
    j["min_scaled_jacobian"] = q.min_scaled_jacobian;
    j["mean_scaled_jacobian"] = q.mean_scaled_jacobian;
    j["max_skewness"] = q.max_skewness;
    j["max_non_orthogonality_deg"] = q.max_non_orthogonality_deg;
    j["max_aspect_ratio"] = q.max_aspect_ratio;
    j["max_volume_ratio"] = q.max_volume_ratio;
    j["min_volume"] = q.min_volume;
    if (r.max_surface_distance) j["max_surface_distance_over_h"] = *r.max_surface_distance;
    if (r.length_scale) j["length_scale_h"] = *r.length_scale;
    return j.dump(2) + "\n";
}

}  // namespace hexmesh

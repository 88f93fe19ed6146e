// The quality table and JSON of tet meshes.
#include "hexmesh/quality/tet_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

namespace hexmesh {

std::string format_tet_quality_table(const std::vector<TetQualityColumn>& columns) {
    std::string out;
    if (std::any_of(columns.begin(), columns.end(),
                    [](const TetQualityColumn& c) { return !c.name.empty(); })) {
        out += fmt::format("  {:<32}", "");
        for (const TetQualityColumn& c : columns) out += fmt::format("{:>20}", c.name);
        out += "\n";
    }
    auto row = [&](const std::string& label, auto value) {
        out += fmt::format("  {:<32}", label);
        for (const TetQualityColumn& c : columns) out += fmt::format("{:>20}", value(c));
        out += "\n";
    };
    auto degrees = [](double x) { return fmt::format("{:.2f}", x); };
    row("tets", [](const TetQualityColumn& c) { return std::to_string(c.quality->cells); });
    row("inverted", [](const TetQualityColumn& c) { return std::to_string(c.quality->inverted); });
    row("min dihedral angle (deg)",
        [&](const TetQualityColumn& c) { return degrees(c.quality->min_dihedral); });
    row("max dihedral angle (deg)",
        [&](const TetQualityColumn& c) { return degrees(c.quality->max_dihedral); });
    row("mean min dihedral angle (deg)",
        [&](const TetQualityColumn& c) { return degrees(c.quality->mean_min_dihedral); });
    if (!columns.empty())
        row(fmt::format("slivers (dihedral < {:g} deg)", columns[0].quality->sliver_degrees),
            [](const TetQualityColumn& c) { return std::to_string(c.quality->slivers); });
    row("min radius ratio", [](const TetQualityColumn& c) {
        return fmt::format("{:.3f}", c.quality->min_radius_ratio);
    });
    row("mean radius ratio", [](const TetQualityColumn& c) {
        return fmt::format("{:.3f}", c.quality->mean_radius_ratio);
    });
    auto optional = [](const std::optional<double>& x, const char* format) {
        return x ? fmt::format(fmt::runtime(format), *x) : std::string("-");
    };
    if (std::any_of(columns.begin(), columns.end(),
                    [](const TetQualityColumn& c) { return bool(c.boundary_distance); }))
        row("max boundary distance / h",
            [&](const TetQualityColumn& c) { return optional(c.boundary_distance, "{:.2e}"); });
    if (std::any_of(columns.begin(), columns.end(),
                    [](const TetQualityColumn& c) { return bool(c.crease_distance); }))
        row("max crease distance / h",
            [&](const TetQualityColumn& c) { return optional(c.crease_distance, "{:.2e}"); });
    if (std::any_of(columns.begin(), columns.end(),
                    [](const TetQualityColumn& c) { return bool(c.seconds); }))
        row("time (s)", [&](const TetQualityColumn& c) { return optional(c.seconds, "{:.2f}"); });
    return out;
}

std::string tet_quality_json(const TetQualityReport& q, std::optional<double> boundary_distance) {
    nlohmann::ordered_json j;
    j["valid"] = q.inverted == 0;
    j["cells"] = q.cells;
    j["points"] = q.points;
    j["inverted"] = q.inverted;
    j["min_dihedral_deg"] = q.min_dihedral;
    j["max_dihedral_deg"] = q.max_dihedral;
    j["mean_min_dihedral_deg"] = q.mean_min_dihedral;
    j["slivers"] = q.slivers;
    j["sliver_threshold_deg"] = q.sliver_degrees;
    j["min_radius_ratio"] = q.min_radius_ratio;
    j["mean_radius_ratio"] = q.mean_radius_ratio;
    if (boundary_distance) j["max_boundary_distance_over_h"] = *boundary_distance;
    return j.dump(2) + "\n";
}

}  // namespace hexmesh

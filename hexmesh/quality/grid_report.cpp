// The quality table and quality.json of a block grid.
#include "hexmesh/quality/grid_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <initializer_list>
#include <nlohmann/json.hpp>

namespace hexmesh {
namespace {

// Names take 30 columns and the value ends in column 46; a longer name pushes the value only
// as far as it must (one space at least), and further values follow in 11-wide columns.
std::string table_row(const std::string& name, std::initializer_list<std::string> values) {
    auto value = values.begin();
    std::string line = name.size() <= 30 ? fmt::format("  {:<30}{:>14}", name, *value)
                                         : fmt::format("  {} {:>{}}", name, *value,
                                                       std::max<int>(0, 43 - int(name.size())));
    for (++value; value != values.end(); ++value) line += fmt::format("{:>11}", *value);
    return line + "\n";
}

// Each phase once, in the order it first ran, the seconds of its runs summed.
std::vector<std::pair<std::string, double>> summed_phases(
    const std::vector<std::pair<std::string, double>>& phases) {
    std::vector<std::pair<std::string, double>> summed;
    for (const auto& [name, seconds] : phases) {
        const auto same = std::find_if(summed.begin(), summed.end(),
                                       [&](const auto& p) { return p.first == name; });
        if (same == summed.end())
            summed.emplace_back(name, seconds);
        else
            same->second += seconds;
    }
    return summed;
}

std::string number(double x) {
    return fmt::format("{:.4g}", x);
}

std::string wall_rows(const WallQuality& w) {
    const bool thickness_target = w.first_layer_target > 0;
    const bool growth = w.growth_ratios > 0, growth_target = w.growth_ratio_target > 0;
    auto percent = [](double fraction) { return fmt::format("{:.1f} %", 100 * fraction); };
    std::string out;
    out += table_row("wall cells", {fmt::format("{}", w.wall_cells)});
    out += table_row(
        "first-layer thickness min/mean/max",
        {number(w.first_layer_min), number(w.first_layer_mean), number(w.first_layer_max)});
    out += table_row("  target, within 10 %",
                     {thickness_target ? number(w.first_layer_target) : "-",
                      thickness_target ? percent(w.first_layer_within_10_percent) : "-"});
    out += table_row("  cells through the wall", {fmt::format("{}", w.cells_through_wall)});
    if (w.cells_through_wall > 0)
        out += table_row("    thinnest at",
                         {fmt::format("({:.4g}, {:.4g}, {:.4g})", w.first_layer_min_at.x(),
                                      w.first_layer_min_at.y(), w.first_layer_min_at.z())});
    out += table_row("growth ratio min/mean/max", {growth ? number(w.growth_ratio_min) : "-",
                                                   growth ? number(w.growth_ratio_mean) : "-",
                                                   growth ? number(w.growth_ratio_max) : "-"});
    out += table_row("  target, within 5 %",
                     {growth_target ? number(w.growth_ratio_target) : "-",
                      growth_target ? percent(w.growth_ratio_within_5_percent) : "-"});
    out += table_row("wall orthogonality max/mean (deg)",
                     {fmt::format("{:.2f}", w.orthogonality_max_deg),
                      fmt::format("{:.2f}", w.orthogonality_mean_deg)});
    if (w.hausdorff) out += table_row("Hausdorff distance to surface", {number(*w.hausdorff)});
    if (w.surface_in_cells_max)
        out += table_row("surface to wall in wall cells max/p99",
                         {fmt::format("{:.3f}", *w.surface_in_cells_max),
                          fmt::format("{:.3f}", w.surface_in_cells_p99.value_or(0))});
    if (w.surface_in_cells_at)
        out += table_row("  at",
                         {fmt::format("({:.4g}, {:.4g}, {:.4g})", w.surface_in_cells_at->x(),
                                      w.surface_in_cells_at->y(), w.surface_in_cells_at->z())});
    for (const WallQuality::Stage& s : w.surface_in_cells_by_stage)
        out +=
            table_row("  " + s.name, {fmt::format("{:.3f}", s.max), fmt::format("{:.3f}", s.p99)});
    return out;
}

// A target of 0 (no law) is written as null, and so is what is measured against it.
nlohmann::ordered_json wall_json(const WallQuality& w) {
    auto or_null = [](bool known, double x) { return known ? nlohmann::ordered_json(x) : nullptr; };
    const bool thickness_target = w.first_layer_target > 0;
    const bool growth = w.growth_ratios > 0, growth_target = w.growth_ratio_target > 0;
    nlohmann::ordered_json j;
    j["cells"] = w.wall_cells;
    j["first_layer_thickness"] = {
        {"min", w.first_layer_min},
        {"mean", w.first_layer_mean},
        {"max", w.first_layer_max},
        {"target", or_null(thickness_target, w.first_layer_target)},
        {"fraction_within_10_percent", or_null(thickness_target, w.first_layer_within_10_percent)},
        {"cells_through_wall", w.cells_through_wall},
        {"min_at", {w.first_layer_min_at.x(), w.first_layer_min_at.y(), w.first_layer_min_at.z()}}};
    j["growth_ratio"] = {
        {"samples", w.growth_ratios},
        {"min", or_null(growth, w.growth_ratio_min)},
        {"mean", or_null(growth, w.growth_ratio_mean)},
        {"max", or_null(growth, w.growth_ratio_max)},
        {"target", or_null(growth_target, w.growth_ratio_target)},
        {"fraction_within_5_percent", or_null(growth_target, w.growth_ratio_within_5_percent)}};
    j["orthogonality_deg"] = {{"max", w.orthogonality_max_deg}, {"mean", w.orthogonality_mean_deg}};
    if (w.hausdorff) j["hausdorff_distance"] = *w.hausdorff;
    if (w.grid_to_surface) j["grid_to_surface_distance"] = *w.grid_to_surface;
    if (w.surface_to_grid) j["surface_to_grid_distance"] = *w.surface_to_grid;
    if (w.surface_in_cells_max)
        j["surface_to_wall_in_cells"] = {{"max", *w.surface_in_cells_max},
                                         {"p99", w.surface_in_cells_p99.value_or(0)}};
    if (w.surface_in_cells_max && w.surface_in_cells_at) {
        const Vec3& at = *w.surface_in_cells_at;
        j["surface_to_wall_in_cells"]["at"] = {at.x(), at.y(), at.z()};
        j["surface_to_wall_in_cells"]["distance"] = w.surface_in_cells_distance.value_or(0);
    }
    if (w.surface_in_cells_max && !w.surface_in_cells_by_stage.empty()) {
        nlohmann::ordered_json stages = nlohmann::ordered_json::array();
        for (const WallQuality::Stage& s : w.surface_in_cells_by_stage)
            stages.push_back({{"stage", s.name}, {"max", s.max}, {"p99", s.p99}});
        j["surface_to_wall_in_cells"]["by_stage"] = std::move(stages);
    }
    return j;
}

}  // namespace

bool follows_body(const GridReport& r) {
    return !(r.wall && r.wall->surface_in_cells_max &&
             *r.wall->surface_in_cells_max > follows_body_wall_cells);
}

std::string body_missed(const GridReport& r) {
    if (follows_body(r)) return {};
    const WallQuality& w = *r.wall;
    const Vec3 at = w.surface_in_cells_at.value_or(Vec3::Zero());
    std::string stages;
    for (const WallQuality::Stage& s : w.surface_in_cells_by_stage)
        stages += fmt::format("{}{:.3g}{} {}", stages.empty() ? "" : ", ", s.max,
                              stages.empty() ? " wall cells" : "", s.name);
    return fmt::format(
        "the grid's wall misses the body by {:.3g} ({:.4g} wall cells, more than {}) at the "
        "surface "
        "point ({:.4g}, {:.4g}, {:.4g}): the wall cuts off or bridges that part of the body (a "
        "limb, a "
        "fin, a groove, a sharp edge or corner){}",
        w.surface_in_cells_distance.value_or(0), *w.surface_in_cells_max, follows_body_wall_cells,
        at.x(), at.y(), at.z(), stages.empty() ? "" : "; the wall missed it by at most " + stages);
}

std::string through_wall(const GridReport& r) {
    if (!r.wall || r.wall->cells_through_wall == 0) return {};
    const WallQuality& w = *r.wall;
    const Vec3& at = w.first_layer_min_at;
    return fmt::format(
        "{} wall cells lie through the wall (first-layer thickness <= 0, down to {:.3g} at "
        "({:.4g}, {:.4g}, {:.4g})): the grid folds across the body's surface there",
        w.cells_through_wall, w.first_layer_min, at.x(), at.y(), at.z());
}

std::string through_wall_warning(const GridReport& r, const std::string& prefix) {
    const std::string folded = through_wall(r);
    if (folded.empty()) return {};
    return "\nwarning: " + prefix + folded +
           "; the grid is written, but a solver would see those cells on the body's side of "
           "the wall\n";
}

std::string aspect_ratio_note(const QualityReport& q) {
    if (q.high_aspect_ratio_cells == 0 || !q.solver_valid()) return {};
    return fmt::format(
        "\nnote: {} cells have an aspect ratio over {} (max {:.4g}): OpenFOAM's checkMesh fails "
        "its aspect-ratio check for them (\"High aspect ratio cells found\"), solvers run on "
        "them; a larger first height or more cells along the wall lowers it\n",
        q.high_aspect_ratio_cells, checkmesh_max_aspect_ratio, q.max_aspect_ratio);
}

std::string body_missed_warning(const GridReport& r, const std::string& prefix) {
    const std::string missed = body_missed(r);
    if (missed.empty()) return {};
    return "\nwarning: " + prefix + missed +
           "; the grid is written, but a solver would see the body without that part\n";
}

std::string format_quality_table(const GridReport& r) {
    const QualityReport& q = r.quality;
    std::string out;
    auto row = [&](const char* name, const std::string& value) { out += table_row(name, {value}); };
    row("cells", fmt::format("{}", q.cells));
    row("inverted corner tets", fmt::format("{}", q.inverted_corner_tets));
    row("inverted cells", fmt::format("{}", q.inverted_cells));
    row("negative face pyramids", fmt::format("{}", q.negative_pyramids));
    row("faces at 90 deg or more", fmt::format("{}", q.faces_over_90_deg));
    row("cells of volume <= 0", fmt::format("{}", q.nonpositive_volumes));
    row("faces of skewness over 4", fmt::format("{}", q.highly_skewed_faces));
    row("min scaled Jacobian", fmt::format("{:.4f}", q.min_scaled_jacobian));
    row("mean scaled Jacobian", fmt::format("{:.4f}", q.mean_scaled_jacobian));
    if (q.worst_cell >= 0) {
        const Vec3& c = q.worst_cell_centre;
        row("  worst cell at", fmt::format("({:.4g}, {:.4g}, {:.4g})", c.x(), c.y(), c.z()));
        if (r.worst_cell)
            row("  block, cell", fmt::format("{} ({}, {}, {}){}", r.worst_cell->block,
                                             r.worst_cell->i, r.worst_cell->j, r.worst_cell->k,
                                             r.worst_cell->on_wall ? ", on the wall" : ""));
        else
            row("  cell", fmt::format("{}", q.worst_cell));
    }
    row("max skewness", fmt::format("{:.4f}", q.max_skewness));
    row("max non-orthogonality (deg)", fmt::format("{:.2f}", q.max_non_orthogonality_deg));
    row("max aspect ratio", fmt::format("{:.4g}", q.max_aspect_ratio));
    row("  cells over 1000", fmt::format("{}", q.high_aspect_ratio_cells));
    row("max volume ratio", fmt::format("{:.4g}", q.max_volume_ratio));
    row("min cell volume", fmt::format("{:.4g}", q.min_volume));
    if (r.max_surface_distance)
        row("max |u| / h on the wall", fmt::format("{:.3g}", *r.max_surface_distance));
    if (r.length_scale) row("h (mean wall edge)", fmt::format("{:.4g}", *r.length_scale));
    if (r.wall) out += wall_rows(*r.wall);
    if (!r.phase_seconds.empty()) {
        out += "  time per phase (s)\n";
        double total = 0;
        for (const auto& [name, seconds] : summed_phases(r.phase_seconds)) {
            out += table_row("  " + name, {fmt::format("{:.2f}", seconds)});
            total += seconds;
        }
        out += table_row("  total", {fmt::format("{:.2f}", total)});
    }
    if (r.peak_memory_bytes)
        row("peak memory (MB)", fmt::format("{:.0f}", *r.peak_memory_bytes / 1e6));
    return out;
}

std::string quality_json(const GridReport& r) {
    const QualityReport& q = r.quality;
    nlohmann::ordered_json j;
    j["valid"] = q.solver_valid();
    // null when no surface was measured (a body given by a formula, `hexmesh quality` of a file)
    if (r.wall && r.wall->surface_in_cells_max)
        j["follows_body"] = follows_body(r);
    else
        j["follows_body"] = nullptr;
    j["cells"] = q.cells;
    j["inverted_corner_tets"] = q.inverted_corner_tets;
    j["inverted_cells"] = q.inverted_cells;
    j["negative_face_pyramids"] = q.negative_pyramids;
    j["faces_over_90_deg"] = q.faces_over_90_deg;
    j["nonpositive_volume_cells"] = q.nonpositive_volumes;
    j["highly_skewed_faces"] = q.highly_skewed_faces;
    j["internal_faces"] = q.internal_faces;
    j["min_scaled_jacobian"] = q.min_scaled_jacobian;
    j["mean_scaled_jacobian"] = q.mean_scaled_jacobian;
    if (q.worst_cell >= 0) {
        nlohmann::ordered_json w;
        w["cell"] = q.worst_cell;
        w["centre"] = {q.worst_cell_centre.x(), q.worst_cell_centre.y(), q.worst_cell_centre.z()};
        if (r.worst_cell) {
            w["block"] = r.worst_cell->block;
            w["ijk"] = {r.worst_cell->i, r.worst_cell->j, r.worst_cell->k};
            w["on_wall"] = r.worst_cell->on_wall;
        }
        j["worst_cell"] = w;
    }
    j["max_skewness"] = q.max_skewness;
    j["max_non_orthogonality_deg"] = q.max_non_orthogonality_deg;
    j["max_aspect_ratio"] = q.max_aspect_ratio;
    j["high_aspect_ratio_cells"] = q.high_aspect_ratio_cells;
    j["max_volume_ratio"] = q.max_volume_ratio;
    j["min_volume"] = q.min_volume;
    if (r.max_surface_distance) j["max_surface_distance_over_h"] = *r.max_surface_distance;
    if (r.length_scale) j["length_scale_h"] = *r.length_scale;
    if (r.wall) j["wall"] = wall_json(*r.wall);
    if (!r.phase_seconds.empty()) {
        nlohmann::ordered_json phases = nlohmann::ordered_json::object();
        double total = 0;
        for (const auto& [name, seconds] : summed_phases(r.phase_seconds)) {
            phases[name] = seconds;
            total += seconds;
        }
        j["phases"] = phases;
        j["seconds_total"] = total;
    }
    if (r.peak_memory_bytes) j["peak_memory_mb"] = *r.peak_memory_bytes / 1e6;
    return j.dump(2) + "\n";
}

}  // namespace hexmesh

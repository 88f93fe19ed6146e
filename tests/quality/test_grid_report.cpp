#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"

using namespace hexmesh;

namespace {

GridReport plain_report() {
    GridReport r;
    r.quality.cells = 4056;
    r.quality.min_scaled_jacobian = 0.61;
    r.max_surface_distance = 1e-13;
    r.length_scale = 0.0962;
    return r;
}

WallQuality wall_quality() {
    WallQuality w;
    w.wall_cells = 864;
    w.first_layer_min = 0.0099;
    w.first_layer_mean = 0.01;
    w.first_layer_max = 0.0101;
    w.first_layer_target = 0.01;
    w.first_layer_within_10_percent = 0.75;
    w.growth_ratios = 2592;
    w.growth_ratio_min = 1.19;
    w.growth_ratio_mean = 1.2;
    w.growth_ratio_max = 1.21;
    w.growth_ratio_target = 1.2;
    w.growth_ratio_within_5_percent = 1.0;
    w.orthogonality_max_deg = 3.5;
    w.orthogonality_mean_deg = 0.25;
    w.hausdorff = 0.004;
    w.grid_to_surface = 0.003;
    w.surface_to_grid = 0.004;
    return w;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The line that starts with "  " + name, or "" when there is none.
std::string line_named(const std::string& table, const std::string& name) {
    for (const std::string& line : lines_of(table))
        if (line.rfind("  " + name, 0) == 0) return line;
    return "";
}

// Where the first value of a row ends (column counted from 0): values hold no two spaces in
// a row and are separated by at least two.
size_t first_value_end(const std::string& line, const std::string& name) {
    const size_t start = line.find_first_not_of(' ', 2 + name.size());
    return std::min(line.find("  ", start), line.size());
}

}  // namespace

TEST(QualityReport, WithoutWallTheTableAndJsonAreAsBefore) {
    const GridReport r = plain_report();
    const std::string table = format_quality_table(r);
    EXPECT_NE(table.find("  inverted corner tets                       0\n"), std::string::npos)
        << table;
    EXPECT_NE(table.find("  cells                                   4056\n"), std::string::npos);
    EXPECT_EQ(table.find("first-layer thickness"), std::string::npos);
    EXPECT_EQ(table.find("Hausdorff"), std::string::npos);
    EXPECT_EQ(table.find("time per phase"), std::string::npos);
    EXPECT_NE(table.find("  negative face pyramids                     0\n"), std::string::npos)
        << table;
    EXPECT_NE(table.find("  faces of skewness over 4                   0\n"), std::string::npos)
        << table;
    EXPECT_NE(table.find("    cells over 1000                          0\n"), std::string::npos)
        << table;
    EXPECT_EQ(lines_of(table).size(), 17u);

    const auto j = nlohmann::json::parse(quality_json(r));
    EXPECT_EQ(j.at("cells").get<long>(), 4056);
    EXPECT_TRUE(j.at("valid").get<bool>());
    EXPECT_EQ(j.at("faces_over_90_deg").get<long>(), 0);
    EXPECT_EQ(j.at("highly_skewed_faces").get<long>(), 0);
    EXPECT_EQ(j.at("high_aspect_ratio_cells").get<long>(), 0);
    EXPECT_EQ(aspect_ratio_note(r.quality), "");
    EXPECT_DOUBLE_EQ(j.at("length_scale_h").get<double>(), 0.0962);
    EXPECT_FALSE(j.contains("wall"));
    EXPECT_FALSE(j.contains("phases"));
}

TEST(QualityReport, WallRowsAreAlignedWithTheOthers) {
    GridReport r = plain_report();
    r.wall = wall_quality();
    r.phase_seconds = {{"geometry", 0.012}, {"grid", 1.5}};
    const std::string table = format_quality_table(r);
    // The existing rows are unchanged and come first.
    EXPECT_EQ(table.rfind(format_quality_table(plain_report()), 0), 0u) << table;

    const std::vector<std::pair<std::string, std::string>> rows = {
        {"wall cells", "864"},
        {"first-layer thickness min/mean/max", "0.0099       0.01     0.0101"},
        {"  target, within 10 %", "0.01     75.0 %"},
        {"  cells through the wall", "0"},
        {"growth ratio min/mean/max", "1.19        1.2       1.21"},
        {"  target, within 5 %", "1.2    100.0 %"},
        {"wall orthogonality max/mean (deg)", "3.50       0.25"},
        {"Hausdorff distance to surface", "0.004"},
        {"  geometry", "0.01"},
        {"  grid", "1.50"},
    };
    const size_t column = line_named(table, "cells").size();  // where values end: 46
    EXPECT_EQ(column, 46u);
    for (const auto& [name, values] : rows) {
        const std::string line = line_named(table, name);
        ASSERT_FALSE(line.empty()) << name << "\n" << table;
        EXPECT_EQ(line.substr(line.size() - values.size()), values) << line;
        EXPECT_EQ(first_value_end(line, name), column) << line;
    }
    EXPECT_NE(table.find("\n  time per phase (s)\n    geometry"), std::string::npos) << table;
}

TEST(QualityReport, PhasesRunAgainAreSummedWithTheTotalAndPeakMemory) {
    // A run whose grid is made again (a retry) runs "grid" and "optimization" twice: the table
    // and quality.json show each phase once, its runs summed, then the total.
    GridReport r = plain_report();
    r.phase_seconds = {{"geometry", 0.5},
                       {"grid", 1.0},
                       {"optimization", 10.0},
                       {"grid", 2.0},
                       {"optimization", 20.0}};
    r.peak_memory_bytes = 123.4e6;
    const std::string table = format_quality_table(r);
    EXPECT_NE(table.find("\n  time per phase (s)\n    geometry"), std::string::npos) << table;
    for (const auto& [name, value] :
         std::vector<std::pair<std::string, std::string>>{{"  grid", "3.00"},
                                                          {"  optimization", "30.00"},
                                                          {"  total", "33.50"},
                                                          {"peak memory (MB)", "123"}}) {
        const std::string line = line_named(table, name);
        ASSERT_FALSE(line.empty()) << name << "\n" << table;
        EXPECT_EQ(line.substr(line.size() - value.size()), value) << line;
    }
    EXPECT_EQ(table.find("grid", table.find("  grid") + 8), std::string::npos) << table;
    const auto j = nlohmann::json::parse(quality_json(r));
    EXPECT_DOUBLE_EQ(j["phases"]["grid"].get<double>(), 3.0);
    EXPECT_DOUBLE_EQ(j["phases"]["optimization"].get<double>(), 30.0);
    EXPECT_EQ(j["phases"].size(), 3u);
    EXPECT_DOUBLE_EQ(j["seconds_total"].get<double>(), 33.5);
    EXPECT_DOUBLE_EQ(j["peak_memory_mb"].get<double>(), 123.4);
    // Not measured: no row, no key.
    const GridReport plain = plain_report();
    EXPECT_EQ(format_quality_table(plain).find("peak memory"), std::string::npos);
    EXPECT_FALSE(nlohmann::json::parse(quality_json(plain)).contains("peak_memory_mb"));
}

TEST(QualityReport, UnknownTargetsShowAsDashAndNull) {
    GridReport r = plain_report();
    WallQuality w = wall_quality();
    w.first_layer_target = w.growth_ratio_target = 0;
    w.hausdorff.reset();
    r.wall = w;
    const std::string table = format_quality_table(r);
    const std::string target = line_named(table, "  target, within 10 %");
    EXPECT_EQ(target.substr(target.size() - 12), "-" + std::string(10, ' ') + "-") << target;
    EXPECT_EQ(first_value_end(target, "  target, within 10 %"), 46u) << target;
    EXPECT_EQ(table.find("Hausdorff"), std::string::npos);

    const auto j = nlohmann::json::parse(quality_json(r));
    EXPECT_TRUE(j.at("wall").at("first_layer_thickness").at("target").is_null());
    EXPECT_TRUE(j.at("wall").at("growth_ratio").at("fraction_within_5_percent").is_null());
    EXPECT_FALSE(j.at("wall").contains("hausdorff_distance"));
}

TEST(QualityReport, JsonHoldsTheWallAndPhases) {
    GridReport r = plain_report();
    r.wall = wall_quality();
    r.phase_seconds = {{"geometry", 0.012}, {"grid", 1.5}};
    const auto j = nlohmann::json::parse(quality_json(r));
    EXPECT_EQ(j.at("cells").get<long>(), 4056);
    EXPECT_TRUE(j.at("valid").get<bool>());
    EXPECT_EQ(j.at("faces_over_90_deg").get<long>(), 0);  // existing keys stay
    const auto& w = j.at("wall");
    EXPECT_EQ(w.at("cells").get<long>(), 864);
    EXPECT_DOUBLE_EQ(w.at("first_layer_thickness").at("min").get<double>(), 0.0099);
    EXPECT_DOUBLE_EQ(w.at("first_layer_thickness").at("mean").get<double>(), 0.01);
    EXPECT_DOUBLE_EQ(w.at("first_layer_thickness").at("max").get<double>(), 0.0101);
    EXPECT_DOUBLE_EQ(w.at("first_layer_thickness").at("target").get<double>(), 0.01);
    EXPECT_DOUBLE_EQ(w.at("first_layer_thickness").at("fraction_within_10_percent").get<double>(),
                     0.75);
    EXPECT_EQ(w.at("growth_ratio").at("samples").get<long>(), 2592);
    EXPECT_DOUBLE_EQ(w.at("growth_ratio").at("min").get<double>(), 1.19);
    EXPECT_DOUBLE_EQ(w.at("growth_ratio").at("target").get<double>(), 1.2);
    EXPECT_DOUBLE_EQ(w.at("growth_ratio").at("fraction_within_5_percent").get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(w.at("orthogonality_deg").at("max").get<double>(), 3.5);
    EXPECT_DOUBLE_EQ(w.at("orthogonality_deg").at("mean").get<double>(), 0.25);
    EXPECT_DOUBLE_EQ(w.at("hausdorff_distance").get<double>(), 0.004);
    EXPECT_DOUBLE_EQ(w.at("grid_to_surface_distance").get<double>(), 0.003);
    EXPECT_DOUBLE_EQ(w.at("surface_to_grid_distance").get<double>(), 0.004);
    EXPECT_DOUBLE_EQ(j.at("phases").at("geometry").get<double>(), 0.012);
    EXPECT_DOUBLE_EQ(j.at("phases").at("grid").get<double>(), 1.5);
}

// A wall that misses the surface by more than half a wall cell: follows_body false, the place
// and distance in the JSON, one line naming them; within half a cell, or without a surface
// measured, the grid follows the body.
TEST(QualityReport, AWallThatMissesTheBodyIsNamed) {
    GridReport r = plain_report();
    EXPECT_TRUE(follows_body(r));  // no wall, no surface
    EXPECT_EQ(body_missed(r), "");
    r.wall = wall_quality();
    EXPECT_TRUE(follows_body(r));  // a wall but no surface vertices measured
    r.wall->surface_in_cells_max = 0.5;
    r.wall->surface_in_cells_p99 = 0.2;
    r.wall->surface_in_cells_at = Vec3(0.25, -1.5, 3);
    r.wall->surface_in_cells_distance = 0.031;
    EXPECT_TRUE(follows_body(r));  // exactly half a cell
    EXPECT_TRUE(nlohmann::json::parse(quality_json(r)).at("follows_body").get<bool>());

    r.wall->surface_in_cells_max = 2.4;
    EXPECT_FALSE(follows_body(r));
    EXPECT_EQ(body_missed(r).rfind(
                  "the grid's wall misses the body by 0.031 (2.4 wall cells, more than 0.5) at "
                  "the surface point (0.25, -1.5, 3)",
                  0),
              0u)
        << body_missed(r);
    const auto j = nlohmann::json::parse(quality_json(r));
    EXPECT_TRUE(j.at("valid").get<bool>());  // for the solver: a separate question
    EXPECT_FALSE(j.at("follows_body").get<bool>());
    const auto& s = j.at("wall").at("surface_to_wall_in_cells");
    EXPECT_DOUBLE_EQ(s.at("max").get<double>(), 2.4);
    EXPECT_DOUBLE_EQ(s.at("distance").get<double>(), 0.031);
    EXPECT_EQ(s.at("at"), nlohmann::json::array({0.25, -1.5, 3}));
    EXPECT_NE(line_named(format_quality_table(r), "  at").find("(0.25, -1.5, 3)"),
              std::string::npos)
        << format_quality_table(r);
    EXPECT_FALSE(s.contains("by_stage"));  // not recorded
}

// Wall cells through the wall (first-layer thickness <= 0) are counted in the table and the
// JSON, the thinnest placed, and named in one line and a warning; none: no line, no warning.
TEST(QualityReport, WallCellsThroughTheWallAreCountedAndPlaced) {
    GridReport r = plain_report();
    r.wall = wall_quality();
    EXPECT_EQ(through_wall(r), "");
    EXPECT_EQ(through_wall_warning(r), "");
    EXPECT_EQ(line_named(format_quality_table(r), "    thinnest at"), "");
    r.wall->cells_through_wall = 18;
    r.wall->first_layer_min = -0.0055;
    r.wall->first_layer_min_at = Vec3(-0.05, 0.25, 0.078);
    const std::string table = format_quality_table(r);
    const std::string count = line_named(table, "  cells through the wall");
    EXPECT_EQ(count.substr(count.size() - 2), "18") << table;
    EXPECT_NE(line_named(table, "    thinnest at").find("(-0.05, 0.25, 0.078)"), std::string::npos)
        << table;
    EXPECT_EQ(through_wall(r),
              "18 wall cells lie through the wall (first-layer thickness <= 0, down to -0.0055 "
              "at (-0.05, 0.25, 0.078)): the grid folds across the body's surface there");
    EXPECT_EQ(through_wall_warning(r, "level 2: ").rfind("\nwarning: level 2: 18 wall cells", 0),
              0u);
    const auto j = nlohmann::json::parse(quality_json(r));
    const auto& t = j.at("wall").at("first_layer_thickness");
    EXPECT_EQ(t.at("cells_through_wall").get<int>(), 18);
    EXPECT_EQ(t.at("min_at"), nlohmann::json::array({-0.05, 0.25, 0.078}));
}

// The misses recorded at the stages of the run: one table row each (max, p99), in order, the
// same in the JSON, and named at the end of the line that says the wall misses the body.
TEST(QualityReport, WhereTheWallLeftTheBodyIsNamedStageByStage) {
    GridReport r = plain_report();
    r.wall = wall_quality();
    r.wall->surface_in_cells_max = 4.2;
    r.wall->surface_in_cells_p99 = 2.7;
    r.wall->surface_in_cells_at = Vec3(0, 1, 0);
    r.wall->surface_in_cells_distance = 0.16;
    r.wall->surface_in_cells_by_stage = {{"as placed", 0.619, 0.354},
                                         {"after the surface pass", 1.34, 0.76}};
    const std::string table = format_quality_table(r);
    const std::string placed = line_named(table, "  as placed");
    const std::string surface = line_named(table, "  after the surface pass");
    EXPECT_NE(placed.find("0.619"), std::string::npos) << table;
    EXPECT_NE(placed.find("0.354"), std::string::npos) << table;
    EXPECT_NE(surface.find("1.340"), std::string::npos) << table;
    EXPECT_LT(table.find("  as placed"), table.find("  after the surface pass"));
    const auto stages = nlohmann::json::parse(quality_json(r))
                            .at("wall")
                            .at("surface_to_wall_in_cells")
                            .at("by_stage");
    ASSERT_EQ(stages.size(), 2u);
    EXPECT_EQ(stages[0].at("stage"), "as placed");
    EXPECT_DOUBLE_EQ(stages[0].at("max").get<double>(), 0.619);
    EXPECT_DOUBLE_EQ(stages[1].at("p99").get<double>(), 0.76);
    const std::string missed = body_missed(r);
    EXPECT_NE(missed.find("; the wall missed it by at most 0.619 wall cells as placed, 1.34 after "
                          "the surface pass"),
              std::string::npos)
        << missed;
}

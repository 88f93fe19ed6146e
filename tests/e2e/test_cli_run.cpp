#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/vtk_mesh.h"

using namespace hexmesh;
using namespace hexmesh::test_support;
namespace fs = std::filesystem;

namespace {

const fs::path out_dir = scratch("sphere");

// Runs the bundled sphere case once for all tests of this file.
class SphereRun : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        fs::remove_all(out_dir);
        result = run_hexmesh("run cases/sphere/case.json -o '" + out_dir.string() + "'");
    }
    static void TearDownTestSuite() { fs::remove_all(out_dir); }
    static CommandResult result;
};
CommandResult SphereRun::result;

}  // namespace

TEST_F(SphereRun, SucceedsAndSaysWhereTheGridIs) {
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find("written: " + (out_dir / "grid.vtm").string()), std::string::npos)
        << result.out;
    EXPECT_NE(result.out.find("inverted corner tets"), std::string::npos);
    EXPECT_TRUE(result.err.empty()) << result.err;
}

TEST_F(SphereRun, QualityJsonMeetsTheTargets) {
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const auto q = nlohmann::json::parse(read_text(out_dir / "quality.json"));
    EXPECT_TRUE(q.at("valid").get<bool>());
    EXPECT_EQ(q.at("inverted_corner_tets").get<long>(), 0);
    EXPECT_GT(q.at("cells").get<long>(), 25000);
    EXPECT_LT(q.at("cells").get<long>(), 40000);
    EXPECT_GE(q.at("min_scaled_jacobian").get<double>(), 0.3);
    EXPECT_LT(q.at("max_surface_distance_over_h").get<double>(), 1e-6);
    for (const char* key : {"mean_scaled_jacobian", "max_skewness", "max_non_orthogonality_deg",
                            "max_aspect_ratio", "max_volume_ratio", "min_volume"})
        EXPECT_TRUE(q.contains(key)) << key;
}

TEST_F(SphereRun, GridReadsBackWithVtk) {
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const HexMesh mesh = read_vtk_mesh((out_dir / "grid.vtm").string());
    const auto q = nlohmann::json::parse(read_text(out_dir / "quality.json"));
    EXPECT_EQ(mesh.num_cells(), q.at("cells").get<long>());
    for (const Vec3& p : mesh.points) EXPECT_LE(p.norm(), 1.0 + 1e-9);
}

TEST_F(SphereRun, QualityCommandAgreesWithTheRun) {
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const CommandResult q = run_hexmesh("quality --json '" + (out_dir / "grid.vtm").string() + "'");
    ASSERT_EQ(q.exit_code, 0) << q.err;
    const auto from_file = nlohmann::json::parse(q.out);
    const auto from_run = nlohmann::json::parse(read_text(out_dir / "quality.json"));
    for (const char* key : {"cells", "inverted_corner_tets", "inverted_cells"})
        EXPECT_EQ(from_file.at(key), from_run.at(key)) << key;
    for (const char* key : {"min_scaled_jacobian", "max_non_orthogonality_deg", "max_skewness"})
        EXPECT_NEAR(from_file.at(key).get<double>(), from_run.at(key).get<double>(), 1e-9) << key;
}

TEST_F(SphereRun, IndependentCheckerAgrees) {
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const fs::path checker =
        fs::path(HEXMESH_SOURCE_DIR) / ".." / "shared" / "tools" / "check_grid.py";
    if (!fs::exists(checker)) GTEST_SKIP() << "no " << checker << " beside the project";
    if (run_command("/usr/bin/python3 -c 'import vtk'").exit_code != 0)
        GTEST_SKIP() << "python3-vtk9 is not installed";
    const CommandResult c = run_command("/usr/bin/python3 '" + checker.string() + "' '" +
                                        (out_dir / "grid.vtm").string() + "' --json");
    EXPECT_EQ(c.exit_code, 0) << c.out << c.err;
    const auto j = nlohmann::json::parse(c.out);
    const auto q = nlohmann::json::parse(read_text(out_dir / "quality.json"));
    EXPECT_EQ(j.at("inverted").get<long>(), 0);
    EXPECT_EQ(j.at("hexes").get<long>(), q.at("cells").get<long>());
    EXPECT_GE(j.at("min_sj").get<double>(), 0.3);
}

// A body thinner than the boundary layer asked for (8 layers 0.119 thick in a disc 0.1 thick):
// the lines there take fewer layers of the same first height, the log says how many lines and
// where, and the grid is written valid.
TEST(CliRun, ThinBodyTakesFewerLayersThere) {
    const fs::path dir = scratch("thin_layers");
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "case.json") << R"({"geometry": {"ellipsoid": {"center": [0, 0, 0],
                                                      "semi_axes": [1, 1, 0.05]}},
        "grid": {"topology": "o-h", "cells_per_edge": 8, "wall_cells": 10},
        "boundary_layer": {"first_height": 0.005, "growth_ratio": 1.3, "layers": 8}})";
    const CommandResult r = run_hexmesh("run '" + (dir / "case.json").string() + "' -o '" +
                                        (dir / "out").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("the body is thin for the boundary layer's 8 layers (0.1193 thick) on "),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("they take fewer layers of the same first height, down to "),
              std::string::npos)
        << r.out;
    const auto q = nlohmann::json::parse(read_text(dir / "out" / "quality.json"));
    EXPECT_TRUE(q.at("valid").get<bool>());
    EXPECT_EQ(q.at("inverted_cells").get<long>(), 0);
    fs::remove_all(dir);
}

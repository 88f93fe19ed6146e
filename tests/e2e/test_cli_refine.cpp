// `hexmesh run` with a refinement family, `hexmesh refine` and `hexmesh gci`, as a user runs them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/vtk_mesh.h"

using namespace hexmesh;
using namespace hexmesh::test_support;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path family_dir = scratch("family");
const fs::path refined_dir = scratch("refined");

// A small sphere family, run once for the tests of this file, then its level 1 refined by
// `hexmesh refine` (the case found through grid.case.json).
class SphereFamily : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        fs::remove_all(family_dir);
        fs::remove_all(refined_dir);
        fs::create_directories(family_dir);
        std::ofstream(scratch("family_case.json")) << R"({
          "geometry": {"sphere": {"center": [0, 0, 0], "radius": 1.0}},
          "grid": {"cells_per_edge": 8, "wall_cells": 6},
          "boundary_layer": {"first_height": 0.02, "growth_ratio": 1.2, "layers": 3},
          "solver": {"optimize_iterations": 5},
          "refinement": {"levels": 3}
        })";
        run = run_hexmesh("run '" + scratch("family_case.json").string() + "' -o '" +
                          family_dir.string() + "'");
        refine = run_hexmesh("refine '" + (family_dir / "level_1" / "grid.vtm").string() +
                             "' -o '" + refined_dir.string() + "'");
    }
    static void TearDownTestSuite() {
        fs::remove_all(family_dir);
        fs::remove_all(refined_dir);
        fs::remove(scratch("family_case.json"));
    }
    static CommandResult run, refine;
};
CommandResult SphereFamily::run, SphereFamily::refine;

}  // namespace

TEST_F(SphereFamily, RunWritesEveryLevelAndTheFamilyTable) {
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    for (int level = 1; level <= 3; ++level) {
        const fs::path dir = family_dir / ("level_" + std::to_string(level));
        EXPECT_TRUE(fs::exists(dir / "grid.vtm")) << dir;
        EXPECT_TRUE(fs::exists(dir / "quality.json")) << dir;
        EXPECT_TRUE(fs::exists(dir / "grid.case.json")) << dir;
    }
    const json family = json::parse(read_text(family_dir / "family.json"));
    ASSERT_EQ(family.at("levels").size(), 3u);
    const long cells = 8 * 8 * 8 + 6 * 8 * 8 * 6;
    EXPECT_EQ(family["levels"][0]["cells"].get<long>(), cells);
    EXPECT_EQ(family["levels"][2]["cells"].get<long>(), 64 * cells);
    EXPECT_NE(run.out.find("grid-convergence family"), std::string::npos) << run.out;
}

TEST_F(SphereFamily, FirstLayerHalvesAndGrowthRatioTakesItsSquareRoot) {
    ASSERT_EQ(run.exit_code, 0) << run.err;
    // A first cell h of ratio r holds two cells h / (1 + sqrt(r)) and sqrt(r) h / (1 + sqrt(r)).
    const json levels = json::parse(read_text(family_dir / "family.json")).at("levels");
    double r = 1.2;
    for (size_t l = 0; l + 1 < levels.size(); ++l, r = std::sqrt(r)) {
        const double h0 = levels[l]["first_layer_mean"], h1 = levels[l + 1]["first_layer_mean"];
        EXPECT_NEAR(h1 / h0, 1 / (1 + std::sqrt(r)), 0.02) << l;
    }
    // The mean over the layers: each coarse cell is split by the refined law (1.0935 measured
    // against 1.0954; 1.116 when the split followed cubic stencils in the index).
    const json fine = json::parse(read_text(family_dir / "level_2" / "quality.json"));
    EXPECT_NEAR(fine.at("wall").at("growth_ratio").at("mean").get<double>(), std::sqrt(1.2), 0.005);
}

TEST_F(SphereFamily, EveryLevelIsValidAndKeepsItsMinScaledJacobian) {
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const json levels = json::parse(read_text(family_dir / "family.json")).at("levels");
    for (size_t l = 0; l < levels.size(); ++l) {
        const json q = json::parse(
            read_text(family_dir / ("level_" + std::to_string(l + 1)) / "quality.json"));
        EXPECT_TRUE(q.at("valid").get<bool>()) << l;
        EXPECT_LT(q.at("max_surface_distance_over_h").get<double>(), 1e-3) << l;
        if (l > 0) {
            EXPECT_GE(levels[l]["min_scaled_jacobian"].get<double>(),
                      levels[l - 1]["min_scaled_jacobian"].get<double>() - 0.05);
        }
    }
}

TEST_F(SphereFamily, RefineCommandWritesTheNextLevelOfTheFamily) {
    ASSERT_EQ(refine.exit_code, 0) << refine.out << refine.err;
    const HexMesh mine = read_vtk_mesh((refined_dir / "grid.vtm").string());
    const HexMesh runs = read_vtk_mesh((family_dir / "level_2" / "grid.vtm").string());
    EXPECT_EQ(mine.num_cells(), runs.num_cells());
    const json q = json::parse(read_text(refined_dir / "quality.json"));
    EXPECT_TRUE(q.at("valid").get<bool>());
    EXPECT_TRUE(fs::exists(refined_dir / "grid.case.json"));
}

// `refine` makes, measures and writes its level block by block; `run` holds its levels whole.
// The grids are the same node for node, blocks conforming (shared nodes read back as one).
TEST_F(SphereFamily, RefineCommandWritesBlockByBlockTheGridRunHoldsWhole) {
    ASSERT_EQ(refine.exit_code, 0) << refine.err;
    EXPECT_NE(refine.out.find("block wall_xmin"), std::string::npos) << refine.out;
    const BlockGrid mine = read_vtk_block_grid((refined_dir / "grid.vtm").string());
    const BlockGrid runs = read_vtk_block_grid((family_dir / "level_2" / "grid.vtm").string());
    ASSERT_EQ(mine.points.size(), runs.points.size());
    ASSERT_EQ(mine.blocks.size(), runs.blocks.size());
    for (size_t b = 0; b < mine.blocks.size(); ++b) {
        EXPECT_EQ(mine.blocks[b].name, runs.blocks[b].name);
        for (size_t m = 0; m < mine.blocks[b].node_ids.size(); ++m)
            ASSERT_EQ(mine.points[mine.blocks[b].node_ids[m]],
                      runs.points[runs.blocks[b].node_ids[m]])
                << "block " << b << " node " << m;
    }
    const json a = json::parse(read_text(refined_dir / "quality.json"));
    const json b = json::parse(read_text(family_dir / "level_2" / "quality.json"));
    EXPECT_EQ(a.at("min_scaled_jacobian").get<double>(), b.at("min_scaled_jacobian").get<double>());
    EXPECT_EQ(a.at("cells").get<long>(), b.at("cells").get<long>());
}

TEST_F(SphereFamily, RefinedGridContainsEveryCoarseNode) {
    ASSERT_EQ(refine.exit_code, 0) << refine.err;
    const BlockGrid coarse = read_vtk_block_grid((family_dir / "level_1" / "grid.vtm").string());
    const BlockGrid fine = read_vtk_block_grid((refined_dir / "grid.vtm").string());
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        const Block &c = coarse.blocks[b], &f = fine.blocks[b];
        ASSERT_EQ(f.nodes.ni, 2 * c.nodes.ni - 1);
        for (int k = 0; k < c.nodes.nk; ++k)
            for (int j = 0; j < c.nodes.nj; ++j)
                for (int i = 0; i < c.nodes.ni; ++i)
                    ASSERT_EQ(fine.points[f.node(2 * i, 2 * j, 2 * k)],
                              coarse.points[c.node(i, j, k)]);
    }
}

TEST(CliRefine, MissingGridIsOneErrorLine) {
    const CommandResult r =
        run_hexmesh("refine no/such/grid.vtm -o '" + scratch("nothing").string() + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("no/such/grid.vtm"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(scratch("nothing")));
}

namespace {

// Runs `case_json` into scratch(name) and refines its grid into scratch(name + "_refined").
std::pair<CommandResult, CommandResult> run_then_refine(const std::string& name,
                                                        const std::string& case_json) {
    const fs::path dir = scratch(name), refined = scratch(name + "_refined"),
                   case_path = scratch(name + "_case.json");
    fs::remove_all(dir);
    fs::remove_all(refined);
    std::ofstream(case_path) << case_json;
    const CommandResult r =
        run_hexmesh("run '" + case_path.string() + "' -o '" + dir.string() + "'");
    const CommandResult f =
        run_hexmesh("refine '" + (dir / "grid.vtm").string() + "' -o '" + refined.string() + "'");
    fs::remove(case_path);
    return {r, f};
}

}  // namespace

// Cells over checkMesh's aspect-ratio limit (a first layer far thinner than the wall cells, on
// a box, whose flat faces keep every face pyramid positive): `run` and `refine` both write the
// grid (solvers run on it) and say so in one note.
TEST(CliRefine, NotesCellsOverCheckMeshsAspectRatioLimitAsRunDoes) {
    const auto [r, f] = run_then_refine("thin_box", R"({
      "geometry": {"box": {"center": [0, 0, 0], "size": [2, 2, 2]}},
      "grid": {"cells_per_edge": 8, "wall_cells": 6},
      "boundary_layer": {"first_height": 1e-7, "growth_ratio": 1.2, "layers": 3},
      "solver": {"optimize_iterations": 5}
    })");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    ASSERT_EQ(f.exit_code, 0) << f.out << f.err;
    for (const CommandResult* c : {&r, &f})
        EXPECT_NE(c->out.find("cells have an aspect ratio over 1000"), std::string::npos) << c->out;
    EXPECT_TRUE(fs::exists(scratch("thin_box_refined") / "grid.vtm"));
    fs::remove_all(scratch("thin_box"));
    fs::remove_all(scratch("thin_box_refined"));
}

// A first layer of 1e-7 on a sphere whose wall cells are 0.18 wide: a refined wall face warps by
// more than its cell is thick (96 face pyramids of negative volume, no inverted cell). `refine`
// refuses such a level as `run` does its levels: one error line names what a solver refuses and
// nothing is written. (It wrote the level with exit code 0; before that, its wall lines were
// interpolated across the layers from cells 10^5 times longer and crossed: 1512 inverted
// cells.)
TEST(CliRefine, WritesNoLevelASolverRefuses) {
    const auto [r, f] = run_then_refine("thin_sphere", R"({
      "geometry": {"sphere": {"center": [0, 0, 0], "radius": 1.0}},
      "grid": {"cells_per_edge": 8, "wall_cells": 6},
      "boundary_layer": {"first_height": 1e-7, "growth_ratio": 1.2, "layers": 3},
      "solver": {"optimize_iterations": 5}
    })");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const fs::path refined = scratch("thin_sphere_refined");
    EXPECT_NE(f.exit_code, 0) << f.out;
    EXPECT_EQ(count_lines(f.err), 1) << f.err;
    EXPECT_NE(f.err.find("cells that a finite-volume solver refuses: "), std::string::npos)
        << f.err;
    EXPECT_NE(f.err.find("face pyramids of negative volume"), std::string::npos) << f.err;
    EXPECT_EQ(f.err.find("inverted"), std::string::npos) << f.err;
    EXPECT_FALSE(fs::exists(refined));
    fs::remove_all(scratch("thin_sphere"));
    fs::remove_all(refined);
}

TEST(CliGci, ReproducesCelikTable1) {
    // Celik et al., J. Fluids Eng. 130 (2008) 078001, Table 1: phi = 6.063, 5.972, 5.863 on
    // N = 18000, 8000, 4500 cells (2D: r21 = 1.5, r32 = 4/3); p = 1.53, phi_ext = 6.1685,
    // e_a = 1.5 %, e_ext = 1.7 %, GCI_fine = 2.2 %.
    const CommandResult r = run_hexmesh("gci 6.063 5.972 5.863 --ratio 1.5 --ratio32 1.333333333");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("observed order p                    1.53"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("phi_ext^21       6.168"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("GCI_fine^21                         2.17"), std::string::npos) << r.out;
}

TEST(CliGci, SaysWhichRatioItAssumed) {
    const CommandResult r = run_hexmesh("gci 2 5 17");  // phi = 1 + h^2, h = 1, 2, 4
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("refinement ratios r21, r32          2 2"), std::string::npos) << r.out;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;  // p = 2 for the default --order 2: no more
    EXPECT_NE(r.err.find("warning: gci: no --ratio given: assumed refinement ratio h2/h1 = 2 "
                         "and h3/h2 = 2"),
              std::string::npos)
        << r.err;
    const CommandResult given = run_hexmesh("gci 2 5 17 --ratio 2");
    ASSERT_EQ(given.exit_code, 0) << given.err;
    EXPECT_EQ(given.err, "");
}

TEST(CliGci, WarnsWhenTheOrderIsFarBelowTheSchemes) {
    // p = log2(1.1975) = 0.26 on ratio 2: far below a second-order scheme's 2, as expected of
    // a first-order scheme's 0.5 (below half of 1, still: p < 0.5).
    const CommandResult r = run_hexmesh("gci 1 1.1 1.21975 --ratio 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("observed order p                    0.26"), std::string::npos) << r.out;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("warning: gci: observed order p = 0.26 is below 0.5 times the formal "
                         "order 2 (p < 1): the three grids are not in the asymptotic range"),
              std::string::npos)
        << r.err;
    const CommandResult first = run_hexmesh("gci 1 1.1 1.21975 --ratio 2 --order 0.5");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    EXPECT_EQ(first.err, "");
}

TEST(CliGci, WarnsWhenTheOrderIsFarAboveTheSchemes) {
    // phi = 1 + h^5 on ratio 2: p = 5 against the default second order.
    const CommandResult r = run_hexmesh("gci 2 33 1025 --ratio 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("observed order p = 5 is above 2 times the formal order 2 (p > 4)"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(run_hexmesh("gci 2 33 1025 --ratio 2 --order 4").err, "");
}

TEST(CliGci, FormalOrderMustBePositive) {
    const CommandResult r = run_hexmesh("gci 2 5 17 --order 0");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--order"), std::string::npos) << r.err;
}

TEST(CliGci, ZeroDifferenceIsOneErrorLine) {
    const CommandResult r = run_hexmesh("gci 1.0 1.0 2.0");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("differ"), std::string::npos) << r.err;
}

TEST(CliGci, NonMonotoneValuesAreOneErrorLine) {
    const CommandResult r = run_hexmesh("gci 6.0042 5.9624 6.0909");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("not monotone"), std::string::npos) << r.err;
}

// A family of a body with sharp creases (cases/box_cylinder's body, its axis found): the
// refined level keeps the thin first cells next to the rims on their side of the creases, and
// stays valid with a fair minimum scaled Jacobian (448 inverted cells when the interpolation
// reached across the creases).
TEST(SharpFamily, BoxWithCylinderRefinesToAValidLevel) {
    const fs::path dir = scratch("sharp_family");
    fs::remove_all(dir);
    std::ofstream(scratch("sharp_family_case.json")) << R"({
      "geometry": {"union": [
        {"box": {"center": [0, 0, 0], "size": [2, 2, 1.2]}},
        {"cylinder": {"center": [0, 0, 0.5], "radius": 0.6, "height": 1.4}}]},
      "grid": {"cells_per_edge": 12, "wall_cells": 8, "core_size": 0.55},
      "boundary_layer": {"first_height": 0.005, "growth_ratio": 1.2, "layers": 5},
      "refinement": {"levels": 2}
    })";
    const CommandResult r = run_hexmesh("run '" + scratch("sharp_family_case.json").string() +
                                        "' -o '" + dir.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json levels = json::parse(read_text(dir / "family.json")).at("levels");
    ASSERT_EQ(levels.size(), 2u);
    EXPECT_GT(levels[1].at("min_scaled_jacobian").get<double>(), 0.3);
    const json level_2 = json::parse(read_text(dir / "level_2" / "quality.json"));
    EXPECT_TRUE(level_2.at("valid").get<bool>());
    EXPECT_EQ(level_2.at("inverted_corner_tets").get<long>(), 0);
    fs::remove_all(dir);
    fs::remove(scratch("sharp_family_case.json"));
}

// The exterior grid of a 4 x 2 x 1 box refines to a valid level: its lines have all turned to
// the far field within half the box's diagonal, so the cells beside the edges' lines (which
// leave at 45 degrees) are not ten times wider than their neighbours further out, where the
// refinement's cubic stencils overshot and inverted 12 792 cells.
TEST(SharpFamily, BoxExteriorRefinesToAValidLevel) {
    const fs::path dir = scratch("box_exterior_family");
    fs::remove_all(dir);
    std::ofstream(scratch("box_exterior_family_case.json")) << R"({
      "geometry": {"box": {"center": [0, 0, 0], "size": [4, 2, 1]}},
      "domain": "exterior",
      "far_field": {"shape": "sphere", "size": 20},
      "grid": {"cells_per_edge": 16, "wall_cells": 32},
      "boundary_layer": {"first_height": 0.01, "growth_ratio": 1.15, "layers": 10},
      "refinement": {"levels": 2}
    })";
    const CommandResult r =
        run_hexmesh("run '" + scratch("box_exterior_family_case.json").string() + "' -o '" +
                    dir.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json levels = json::parse(read_text(dir / "family.json")).at("levels");
    ASSERT_EQ(levels.size(), 2u);
    EXPECT_GT(levels[0].at("min_scaled_jacobian").get<double>(), 0.5);
    EXPECT_GT(levels[1].at("min_scaled_jacobian").get<double>(), 0.5);
    const json level_1 = json::parse(read_text(dir / "level_1" / "quality.json"));
    EXPECT_LT(level_1.at("max_volume_ratio").get<double>(), 8.0);
    fs::remove_all(dir);
    fs::remove(scratch("box_exterior_family_case.json"));
}

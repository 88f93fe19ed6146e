// What checkMesh fails and the quality report must not call valid: grids built by hand, written
// as OpenFOAM cases, checked by checkMesh and measured by us.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "export_test_support.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/openfoam_mesh.h"
#include "tests/hand_grids.h"

using namespace hexmesh;
using namespace hexmesh::test_export;
using hexmesh::test::leaning_cells;

namespace {

// A cell from a grid of a body with legs (wall cell of a folded quad): its 8 corner tets are
// positive, but it is turned inside out at its centre, its volume negative and faces lie
// beyond its centre. The quality report counts what checkMesh fails, with checkMesh's numbers,
// and does not call the grid valid.
TEST(OpenFoam, QualityCountsTheCellChecksCheckMeshFails) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    BlockGrid grid;
    grid.points = {{-0.141865, 0.190517, 0.212616}, {-0.143186, 0.199647, 0.204166},
                   {-0.158641, 0.160889, 0.142733}, {-0.156454, 0.15972, 0.139122},
                   {-0.143301, 0.190185, 0.211333}, {-0.143869, 0.197249, 0.201958},
                   {-0.146059, 0.159576, 0.147823}, {-0.152377, 0.160523, 0.140178}};
    grid.kinds.assign(8, VertexKind::interior);
    Block b;
    b.name = "cell";
    b.nodes = {2, 2, 2};
    b.node_ids = {0, 1, 3, 2, 4, 5, 7, 6};  // (i, j, k) order of the VTK corners above
    b.face_patch = {"wall", "wall", "wall", "wall", "wall", "wall"};
    grid.blocks = {b};
    const QualityReport q = measure_quality(grid);
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_FALSE(q.solver_valid());
    EXPECT_LT(q.min_scaled_jacobian, -0.9);

    const fs::path dir = scratch("openfoam_refused_cell");
    write_openfoam_mesh(grid, (dir / "case").string());
    const ToolRun r = run_tool(check_mesh_command(dir / "case"));
    EXPECT_NE(r.output.find("Failed"), std::string::npos) << r.output;
    EXPECT_EQ(number_after(r.output, "Error in face pyramids: "), double(q.negative_pyramids))
        << r.output;
    EXPECT_EQ(number_after(r.output, "Number of negative volume cells: "),
              double(q.nonpositive_volumes))
        << r.output;
    EXPECT_GT(q.negative_pyramids, 0);
    EXPECT_EQ(q.nonpositive_volumes, 1);
    fs::remove_all(dir);
}

// A face whose skewness is over 4 fails checkMesh although every cell passes its cell checks;
// the report counts it with checkMesh's number, names both cells as refused and does not call
// the grid valid. Without the lean, both agree the grid is fine.
TEST(OpenFoam, QualityCountsTheSkewedFacesCheckMeshFails) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    const BlockGrid grid = leaning_cells(2.0);
    const QualityReport q = measure_quality(grid);
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_EQ(q.negative_pyramids + q.faces_over_90_deg + q.nonpositive_volumes, 0);
    EXPECT_GT(q.max_skewness, 4);
    EXPECT_GT(q.highly_skewed_faces, 0);
    EXPECT_FALSE(q.solver_valid());
    EXPECT_EQ(find_refused_cells(to_hex_mesh(grid)), (std::vector<Id>{0, 1}));

    const fs::path dir = scratch("openfoam_skewed_face");
    write_openfoam_mesh(grid, (dir / "case").string());
    const ToolRun r = run_tool(check_mesh_command(dir / "case"));
    EXPECT_NE(r.output.find("Failed 1 mesh checks"), std::string::npos) << r.output;
    std::smatch m;  // "***Max skewness = 5, 3 highly skew faces detected ..."
    ASSERT_TRUE(std::regex_search(
        r.output, m, std::regex(R"(Max skewness = ([-+.0-9eE]+), ([0-9]+) highly skew faces)")))
        << r.output;
    EXPECT_NEAR(std::stod(m[1]), q.max_skewness, 1e-5 * q.max_skewness);
    EXPECT_EQ(std::stol(m[2]), q.highly_skewed_faces);

    const BlockGrid upright = leaning_cells(0.0);
    EXPECT_TRUE(measure_quality(upright).solver_valid());
    write_openfoam_mesh(upright, (dir / "upright").string());
    const ToolRun ok = run_tool(check_mesh_command(dir / "upright"));
    EXPECT_NE(ok.output.find("Mesh OK."), std::string::npos) << ok.output;
    fs::remove_all(dir);
}

// A cell 2000 times wider than thick: checkMesh fails its aspect-ratio check ("number of cells
// 1"), our report counts the same cell and ratio, and still calls the grid valid (solvers run on
// such cells).
TEST(OpenFoam, QualityCountsTheCellsOverCheckMeshsAspectRatioLimit) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    BlockGrid grid;
    for (int k = 0; k <= 1; ++k)
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= 1; ++i) grid.points.emplace_back(i, j, 0.0005 * k);
    grid.kinds.assign(8, VertexKind::fixed);
    Block b;
    b.name = "flat";
    b.nodes = {2, 2, 2};
    b.node_ids = {0, 1, 2, 3, 4, 5, 6, 7};
    b.face_patch = {"walls", "walls", "walls", "walls", "walls", "walls"};
    grid.blocks = {b};
    const QualityReport q = measure_quality(grid);
    EXPECT_TRUE(q.solver_valid());
    EXPECT_EQ(q.high_aspect_ratio_cells, 1);

    const fs::path dir = scratch("openfoam_flat_cell");
    write_openfoam_mesh(grid, (dir / "case").string());
    const ToolRun r = run_tool(check_mesh_command(dir / "case"));
    std::smatch m;  // "***High aspect ratio cells found, Max aspect ratio: 2000, number of cells 1"
    ASSERT_TRUE(std::regex_search(
        r.output, m,
        std::regex(
            R"(High aspect ratio cells found, Max aspect ratio: ([-+.0-9eE]+), number of cells ([0-9]+))")))
        << r.output;
    EXPECT_NEAR(std::stod(m[1]), q.max_aspect_ratio, 1e-5 * q.max_aspect_ratio);
    EXPECT_EQ(std::stol(m[2]), q.high_aspect_ratio_cells);
    fs::remove_all(dir);
}

}  // namespace

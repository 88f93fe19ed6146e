#include <gtest/gtest.h>

#include <regex>

#include "export_test_support.h"
#include "hexmesh/core/quality.h"
#include "io/gmsh_mesh.h"
#include "io/grid_faces.h"
#include "io/medit_mesh.h"
#include "io/vtk_mesh.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

// Same cells with the same corner coordinates (within `tolerance`), in the same order.
void expect_same_mesh(const HexMesh& got, const HexMesh& want, double tolerance = 0) {
    ASSERT_EQ(got.num_cells(), want.num_cells());
    EXPECT_EQ(got.num_points(), want.num_points());
    for (Id c = 0; c < want.num_cells(); ++c)
        for (int v = 0; v < 8; ++v)
            ASSERT_LE((got.points[got.node(c, v)] - want.points[want.node(c, v)]).norm(), tolerance) << c;
}

}  // namespace

TEST(GridFaces, CountsMatchEulersFaceBalance) {
    const BlockGrid grid = small_o_h_grid();
    const GridFaces faces = make_grid_faces(grid);
    // 6 faces per cell = 2 per internal face + 1 per boundary face.
    EXPECT_EQ(6 * grid.num_cells(), 2 * faces.internal_faces + faces.boundary_faces);
    ASSERT_EQ(faces.patch_names, std::vector<std::string>{"wall"});
    Id previous_owner = -1, previous_neighbour = -1, internal = 0;
    for_each_internal_face(grid, faces, [&](Id owner, Id neighbour, const std::array<Id, 4>&) {
        EXPECT_LT(owner, neighbour);
        EXPECT_TRUE(owner > previous_owner || (owner == previous_owner && neighbour > previous_neighbour));
        previous_owner = owner;
        previous_neighbour = neighbour;
        ++internal;
    });
    EXPECT_EQ(internal, faces.internal_faces);
}

TEST(GridFaces, BlocksThatDoNotConformAtAnInterfaceAreRefusedNamingTheFace) {
    // The O-H grid with one wall block's nodes on the core face moved off its neighbour's:
    // the interface (no patch) now has cell faces that meet nothing.
    BlockGrid grid = small_o_h_grid();
    Block& wall = grid.blocks.back();
    const Id first = Id(grid.points.size());
    for (int j = 0; j < wall.nodes.nj; ++j)
        for (int i = 0; i < wall.nodes.ni; ++i) {
            Id& id = wall.node_ids[wall.nodes.flat(i, j, 0)];
            grid.points.push_back(grid.points[id]);  // same place, another node
            grid.kinds.push_back(grid.kinds[id]);
            id = Id(grid.points.size()) - 1;
        }
    ASSERT_GT(Id(grid.points.size()), first);
    try {
        make_grid_faces(grid);
        FAIL() << "expected a refusal";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        // The first of the two faces met: the core's side of it.
        EXPECT_NE(what.find("face kmax of block 'core' is an interface (no patch), but 16 of its 16 cell faces"),
                  std::string::npos) << what;
        EXPECT_NE(what.find("meet no other block's: the blocks do not conform there"), std::string::npos) << what;
    }
}

TEST(Gmsh, RoundTripThroughOurReader) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("gmsh") / "grid.msh";
    write_gmsh_mesh(grid, file.string());
    expect_same_mesh(read_gmsh_mesh(file.string()), to_hex_mesh(grid));
    EXPECT_EQ(read_vtk_mesh(file.string()).num_cells(), grid.num_cells());  // `quality` path
}

TEST(Gmsh, GmshReadsItWithTheSameElementCounts) {
    if (!have_tool("gmsh")) GTEST_SKIP() << "gmsh not installed (Debian package gmsh)";
    const BlockGrid grid = small_o_h_grid();
    const fs::path dir = scratch("gmsh_tool");
    write_gmsh_mesh(grid, (dir / "grid.msh").string());
    // gmsh parses the file and saves it again in MSH 4.1; reading that back counts what gmsh
    // understood (-0: no meshing, only parse and save).
    const ToolRun r = run_tool("cd '" + dir.string() + "' && gmsh grid.msh -0 -format msh41 -o again.msh");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("Error"), std::string::npos) << r.output;
    // gmsh prints 16 significant digits, so its copy is exact to ~1e-16 relative.
    expect_same_mesh(read_gmsh_mesh((dir / "again.msh").string()), to_hex_mesh(grid), 1e-14);
    const GridFaces faces = make_grid_faces(grid);
    const ToolRun info = run_tool("cd '" + dir.string() + "' && gmsh grid.msh -0 -o /dev/null -v 99");
    std::smatch m;
    // gmsh reports "<N> elements" for what it read (hexahedra + boundary quadrangles).
    const std::string want = std::to_string(grid.num_cells() + faces.boundary_faces) + " elements";
    EXPECT_NE(info.output.find(want), std::string::npos) << info.output;
}

TEST(Medit, RoundTripThroughOurReader) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("medit") / "grid.mesh";
    write_medit_mesh(grid, file.string());
    const HexMesh back = read_medit_mesh(file.string());
    expect_same_mesh(back, to_hex_mesh(grid));
    const QualityReport q = measure_quality(back), want = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_cells, 0);
    EXPECT_EQ(q.min_scaled_jacobian, want.min_scaled_jacobian);
    EXPECT_EQ(read_vtk_mesh(file.string()).num_cells(), grid.num_cells());
}

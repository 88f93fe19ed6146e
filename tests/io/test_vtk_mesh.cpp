#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/case_file.h"
#include "io/vtk_mesh.h"
#include "surface/analytic.h"
#include "tests/scratch_registry.h"
#include "volume/o_h_grid.h"
#include "volume/single_block_grid.h"

using namespace hexmesh;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("hexmesh_test_io_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return hexmesh::test::remove_at_exit(dir);
}

}  // namespace

TEST(VtkMesh, MultiBlockRoundTripMergesInterfaceNodes) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions o;
    o.cells_per_edge = 6;
    o.wall_cells = 3;
    const BlockGrid grid = make_o_h_grid(sphere, o);
    const fs::path file = temp_dir("vtm") / "grid.vtm";
    write_vtk_grid(grid, file.string());
    ASSERT_TRUE(fs::exists(file));
    const HexMesh back = read_vtk_mesh(file.string());
    const HexMesh mesh = to_hex_mesh(grid);
    ASSERT_EQ(back.num_cells(), mesh.num_cells());
    EXPECT_EQ(back.num_points(), mesh.num_points());  // shared nodes written once per block, merged
    for (Id c = 0; c < mesh.num_cells(); ++c)
        for (int v = 0; v < 8; ++v)
            ASSERT_EQ(back.points[back.node(c, v)], mesh.points[mesh.node(c, v)]) << c;
}

TEST(VtkMesh, SingleBlockRoundTripIsBitwise) {
    const Box box(Vec3::Zero(), Vec3(1, 2, 3));
    SingleBlockOptions o;
    o.cells = {3, 4, 5};
    const BlockGrid grid = make_single_block_grid(box, o);
    const fs::path file = temp_dir("vts") / "grid.vts";
    write_vtk_grid(grid, file.string());
    const HexMesh back = read_vtk_mesh(file.string());
    const HexMesh mesh = to_hex_mesh(grid);
    EXPECT_EQ(back.points, mesh.points);
    EXPECT_EQ(back.hexes, mesh.hexes);
}

TEST(VtkMesh, MissingAndBrokenFilesAreInputErrors) {
    EXPECT_THROW(read_vtk_mesh("/nonexistent/grid.vtm"), InputError);
    const fs::path dir = temp_dir("broken");
    std::ofstream(dir / "broken.vts") << "<VTKFile type=\"StructuredGrid\"><oops";
    EXPECT_THROW(read_vtk_mesh((dir / "broken.vts").string()), InputError);
    std::ofstream(dir / "mesh.obj") << "v 0 0 0\n";
    EXPECT_THROW(read_vtk_mesh((dir / "mesh.obj").string()), InputError);
}

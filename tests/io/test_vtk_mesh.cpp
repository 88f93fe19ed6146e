#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "io/case_file.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"
#include "surface/analytic.h"
#include "tests/io/scratch_files.h"
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

namespace {

// A legacy VTK file of one hexahedron over the unit cube's 8 corners, its cell's row given.
std::string one_hex_vtk(const std::string& cell_row, int row_size) {
    std::string text = "# vtk DataFile Version 3.0\none hex\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n";
    for (int c = 0; c < 8; ++c) text += fmt::format("{} {} {}\n", c & 1, (c >> 1) & 1, c >> 2);
    return text + fmt::format("CELLS 1 {}\n{}\nCELL_TYPES 1\n12\n", row_size, cell_row);
}

}  // namespace

TEST(VtkMesh, CellsWithPointIdsOutOfRangeOrTooFewAreRefusedNamingTheCell) {
    const fs::path dir = temp_dir("bad_ids");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {one_hex_vtk("8 0 1 3 2 4 5 7 99", 9), "cell 0 refers to point 99, but the file has points 0 to 7"},
        {one_hex_vtk("8 0 1 3 2 4 5 7 -1", 9), "cell 0 refers to point -1"},
        {one_hex_vtk("7 0 1 3 2 4 5 7", 8), "cell 0 has 7 point ids where its type takes 8"},
    };
    int n = 0;
    for (const auto& [text, message] : cases) {
        const std::string path = (dir / fmt::format("bad{}.vtk", n++)).string();
        std::ofstream(path) << text;
        for (const std::string& what : {test::input_error_of(read_vtk_mesh, path),
                                        test::input_error_of(read_volume_mesh, path)}) {
            EXPECT_NE(what.find(path), std::string::npos) << what;
            EXPECT_NE(what.find(message), std::string::npos) << what;
        }
    }
    // The same file with good ids is read.
    const std::string good = (dir / "good.vtk").string();
    std::ofstream(good) << one_hex_vtk("8 0 1 3 2 4 5 7 6", 9);
    EXPECT_EQ(read_vtk_mesh(good).num_cells(), 1);
    EXPECT_EQ(read_volume_mesh(good).num_hexes(), 1);
}

TEST(VtkMesh, LegacyCellListsThatDisagreeWithTheirDeclaredSizeAreRefusedBeforeVtkReadsThem) {
    // VTK's legacy reader corrupts the heap on such lists ("free(): invalid next size").
    const fs::path dir = temp_dir("cell_lists");
    const std::vector<std::pair<std::string, std::string>> ascii = {
        {one_hex_vtk("8 0 1 3 2 4 5 7 6", 5), "CELLS: row 0 has 8 ids, beyond the 5 values the line declares"},
        {one_hex_vtk("8 0 1 3 2 4 5 7 6", 12), "CELLS: its 1 rows hold 9 values, but the line declares 12"},
        {one_hex_vtk("12 0 1 3 2 4 5 7 6", 9), "CELLS: row 0 has 12 ids, beyond the 9 values"},
    };
    int n = 0;
    for (const auto& [text, message] : ascii) {
        const std::string path = (dir / fmt::format("rows{}.vtk", n++)).string();
        std::ofstream(path) << text;
        for (const std::string& what : {test::input_error_of(read_vtk_mesh, path),
                                        test::input_error_of(read_volume_mesh, path)}) {
            EXPECT_NE(what.find(path + ": " + message), std::string::npos) << what;
        }
    }
    // Binary, VTK 9's layout (OFFSETS and CONNECTIVITY, 64-bit): as written it reads back; with
    // its declared connectivity size changed it is refused.
    VolumeMesh mesh;
    for (int c = 0; c < 12; ++c) mesh.points.emplace_back(c & 1, (c >> 1) & 1, c >> 2);
    mesh.hexes = {0, 1, 3, 2, 4, 5, 7, 6, 4, 5, 7, 6, 8, 9, 11, 10};
    const std::string binary = (dir / "two.vtk").string();
    write_volume_mesh(mesh, binary);
    EXPECT_EQ(read_volume_mesh(binary).num_hexes(), 2);
    EXPECT_EQ(read_vtk_mesh(binary).num_cells(), 2);
    std::ifstream in(binary, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t at = bytes.find("CELLS 3 16");
    ASSERT_NE(at, std::string::npos) << "not VTK 9's layout";
    bytes.replace(at, 10, "CELLS 3 15");
    const std::string mutated = (dir / "mutated.vtk").string();
    std::ofstream(mutated, std::ios::binary) << bytes;
    const std::string what = test::input_error_of(read_volume_mesh, mutated);
    EXPECT_NE(what.find(mutated + ": CELLS: offset 2 is 16, outside [8, 15]"), std::string::npos) << what;
}

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "export_test_support.h"
#include "io/case_file.h"
#include "io/export_grid.h"
#include "io/gmsh_mesh.h"
#include "io/medit_mesh.h"
#include "io/plot3d.h"
#include "io/sample_readers.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"
#include "tests/io/scratch_files.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

bool folder_is_empty(const fs::path& dir) {
    return fs::is_directory(dir) && fs::directory_iterator(dir) == fs::directory_iterator();
}

}  // namespace

TEST(ExportErrors, UnwritablePathGivesOneClearErrorAndNoFile) {
    const BlockGrid grid = small_o_h_grid(3, 2);
    const fs::path dir = scratch("unwritable");
    std::ofstream(dir / "not_a_folder") << "x";
    for (const char* format : {"gmsh", "openfoam", "plot3d", "cgns", "vtk", "medit"}) {
        SCOPED_TRACE(format);
        const fs::path target = dir / "not_a_folder" / "grid.out";
        try {
            export_grid(grid, format, target.string());
            FAIL() << "expected an error";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("not_a_folder"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(target));
    }
}

TEST(ExportErrors, FailureMidWayLeavesNothingUnderTheFinalName) {
    // Three blocks claim the same interface face: the writer throws after staging began.
    BlockGrid grid = small_o_h_grid(3, 2);
    grid.blocks.push_back(grid.blocks[0]);
    grid.blocks.push_back(grid.blocks[0]);
    const fs::path dir = scratch("midway");
    for (const char* format : {"gmsh", "openfoam", "medit"}) {
        SCOPED_TRACE(format);
        EXPECT_THROW(export_grid(grid, format, (dir / "grid.out").string()), std::invalid_argument);
        EXPECT_TRUE(folder_is_empty(dir));  // no final file, no staging folder left
    }
}

TEST(ExportErrors, UnknownFormatIsAnInputError) {
    const BlockGrid grid = small_o_h_grid(3, 2);
    EXPECT_THROW(export_grid(grid, "tecplot", "/tmp/x.plt"), InputError);
    EXPECT_THROW(export_grid(grid, "plot3d-big-endian", "/tmp/x.xyz"), InputError);
}

TEST(VtkBlockGrid, ReadBackRestoresBlocksNamesPatchesAndSharedNodes) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("vtk_block_grid") / "grid.vtm";
    write_vtk_grid(grid, file.string());
    const BlockGrid back = read_vtk_block_grid(file.string());
    ASSERT_EQ(back.blocks.size(), grid.blocks.size());
    EXPECT_EQ(back.points.size(), grid.points.size());
    ASSERT_EQ(back.kinds.size(), back.points.size());
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        EXPECT_EQ(back.blocks[b].name, grid.blocks[b].name);
        EXPECT_EQ(back.blocks[b].face_patch, grid.blocks[b].face_patch);
        ASSERT_EQ(back.blocks[b].nodes.count(), grid.blocks[b].nodes.count());
        for (Id m = 0; m < grid.blocks[b].nodes.count(); ++m)
            ASSERT_EQ(back.points[back.blocks[b].node_ids[m]],
                      grid.points[grid.blocks[b].node_ids[m]]);
    }
    // Shared nodes: the same node topology, so the same ids up to renumbering; vertex kinds
    // follow their nodes.
    std::vector<Id> map(grid.points.size(), -1);
    for (size_t b = 0; b < grid.blocks.size(); ++b)
        for (Id m = 0; m < grid.blocks[b].nodes.count(); ++m) {
            Id& mapped = map[grid.blocks[b].node_ids[m]];
            if (mapped < 0) mapped = back.blocks[b].node_ids[m];
            ASSERT_EQ(mapped, back.blocks[b].node_ids[m]);
            ASSERT_EQ(back.kinds[mapped], grid.kinds[grid.blocks[b].node_ids[m]]);
        }
}

TEST(ExportCli, RunThenExportThenQualityAgree) {
    const fs::path dir = scratch("cli");
    const std::string exe = HEXMESH_EXE;
    const ToolRun run =
        run_tool("cd '" HEXMESH_SOURCE_DIR "' && '" + exe + "' run cases/sphere/case.json -o '" +
                 (dir / "run").string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::string grid = (dir / "run" / "grid.vtm").string();
    for (const char* format : {"gmsh", "medit", "plot3d-c"}) {
        SCOPED_TRACE(format);
        const std::string out = (dir / (std::string("grid.") + format + ".msh")).string();
        const std::string file =
            std::string(format) == "medit"      ? out.substr(0, out.size() - 4) + ".mesh"
            : std::string(format) == "plot3d-c" ? out.substr(0, out.size() - 4) + ".xyz"
                                                : out;
        const ToolRun ex = run_tool("'" + exe + "' export '" + grid + "' --format " + format +
                                    " -o '" + file + "'");
        ASSERT_EQ(ex.exit_code, 0) << ex.output;
        const ToolRun q = run_tool("'" + exe + "' quality '" + file + "' --json");
        ASSERT_EQ(q.exit_code, 0) << q.output;
        EXPECT_NE(q.output.find("\"cells\": 32000"), std::string::npos) << q.output;
    }
    // UGRID: the boundary conditions' file is written (and listed) beside the grid.
    const std::string ugrid = (dir / "grid.ugrid").string();
    const ToolRun ug =
        run_tool("'" + exe + "' export '" + grid + "' --format ugrid -o '" + ugrid + "'");
    ASSERT_EQ(ug.exit_code, 0) << ug.output;
    EXPECT_NE(ug.output.find("written: " + (dir / "grid.mapbc").string()), std::string::npos)
        << ug.output;
    EXPECT_TRUE(fs::exists(dir / "grid.mapbc"));
    const ToolRun bad =
        run_tool("'" + exe + "' export '" + grid + "' --format gmsh -o /proc/version/grid.msh");
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
    EXPECT_NE(bad.output.find("hexmesh: error: "), std::string::npos) << bad.output;
}

TEST(ReadErrors, HeadersPromisingMoreThanTheFileHoldsAreRefusedBeforeAnythingIsSized) {
    const fs::path dir = scratch("headers");
    // Gmsh: a max node tag of 3e9 for two nodes is read with a map, not a 24 GB table; a node
    // count larger than the file is refused at once.
    const std::string sparse = (dir / "sparse.msh").string();
    std::ofstream(sparse)
        << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 3000000000\n3 1 0 2\n"
           "1\n3000000000\n0 0 0\n1 0 0\n$EndNodes\n$Elements\n1 1 1 1\n3 1 5 1\n"
           "1 1 3000000000 1 1 1 1 1 1\n$EndElements\n";
    EXPECT_EQ(read_gmsh_mesh(sparse).num_cells(), 1);
    const std::string huge = (dir / "huge.msh").string();
    std::ofstream(huge)
        << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2000000000 1 2000000000\n";
    std::string what = test::input_error_of(read_gmsh_mesh, huge);
    EXPECT_NE(what.find("2000000000 nodes in 1 blocks do not fit in the file's"), std::string::npos)
        << what;
    // Plot3D (ASCII): 99999^3 points, dims 0 0 0, and data beyond what the header announces.
    const std::vector<std::pair<std::string, std::string>> plot3d = {
        {"1\n99999 99999 99999\n0 0 0\n", "ni is 99999; expected a whole number in [2, "},
        {"1\n9 9 9\n" + std::string(300, ' ') + "0 0 0\n",
         "block 1 has dims 9 9 9: more coordinates than the file's"},
        {"1\n0 0 0\n1 2 3 4 5 6\n", "ni is 0; expected a whole number in [2,"},
    };
    int n = 0;
    for (const auto& [text, message] : plot3d) {
        const std::string path = (dir / fmt::format("bad{}.xyz", n++)).string();
        std::ofstream(path) << text;
        what = test::input_error_of(read_plot3d, path);
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(message), std::string::npos) << what;
    }
    std::string cube = "1\n2 2 2\n";
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 8; ++c) cube += fmt::format("{} ", (c >> a) & 1);
    const std::string good = (dir / "cube.xyz").string(), longer = (dir / "longer.xyz").string();
    std::ofstream(good) << cube << "\n";
    std::ofstream(longer) << cube << "\n7 7 7\n";
    EXPECT_EQ(read_plot3d(good).num_cells(), 1);
    what = test::input_error_of(read_plot3d, longer);
    EXPECT_NE(what.find("more data after the 24 coordinates the header announces"),
              std::string::npos)
        << what;
}

namespace {

HexMesh read_volume_mesh_hexes(const std::string& path) {
    const VolumeMesh m = read_volume_mesh(path);
    return HexMesh{m.points, m.hexes};
}

// The inputs the fuzz targets (tests/fuzz) found.
fs::path fuzz_regressions() {
    return fs::path(HEXMESH_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
}

}  // namespace

// Inputs the fuzz targets (tests/fuzz) found: each is refused with one clear error. Legacy
// VTK files:
TEST(ReadErrors, FuzzFindingsInLegacyVtkAreRefused) {
    const fs::path dir = fuzz_regressions();
    std::string what;
    // A legacy VTK file with a misspelt keyword: VTK's reader leaked its cells on it.
    what = test::input_error_of(read_vtk_mesh, (dir / "vtk_unknown_keyword.vtk").string());
    EXPECT_NE(what.find("unknown keyword 'CELL$_TYPES' in the UNSTRUCTURED_GRID section"),
              std::string::npos)
        << what;
    // OFFSETS in a file whose header says version 0.1: VTK read rows there, and crashed. No
    // version before 1.0 exists.
    what =
        test::input_error_of(read_vtk_mesh, (dir / "vtk_offsets_in_a_version_4_file.vtk").string());
    EXPECT_NE(what.find("vtk_offsets_in_a_version_4_file.vtk:1: version 0.1: this reader knows "
                        "versions 1.0 to 5.1"),
              std::string::npos)
        << what;
    // A dataset kind VTK does not know: its reader leaked on it.
    what = test::input_error_of(read_vtk_mesh, (dir / "vtk_unknown_dataset.vtk").string());
    EXPECT_NE(what.find("unknown dataset 'UNSTRUCTURED_GRIDshort'"), std::string::npos) << what;
    // Version "5.+": VTK took the cell lists as rows and crashed.
    what = test::input_error_of(read_vtk_mesh, (dir / "vtk_version_not_a_number.vtk").string());
    EXPECT_NE(what.find("'# vtk DataFile Version 5.+': expected a version of two numbers"),
              std::string::npos)
        << what;
    // A pixel whose ids lie beyond the points: VTK read them building the cell, and crashed.
    const std::string pixel = (dir / "vtk_pixel_with_ids_beyond_the_points.vtk").string();
    for (const std::string& message : {test::input_error_of(read_vtk_mesh, pixel),
                                       test::input_error_of(read_volume_mesh_hexes, pixel)})
        EXPECT_NE(
            message.find(
                "CELLS: cell 0 refers to point 9007199254740999, but the file has points 0 to 7"),
            std::string::npos)
            << message;
}

// Plot3D, Gmsh, PLY and Medit files.
TEST(ReadErrors, FuzzFindingsInPlot3dGmshPlyAndMeditAreRefused) {
    const fs::path dir = fuzz_regressions();
    // A Fortran-record header whose block count times 12 overflowed an int (UBSan).
    std::string what = test::input_error_of(
        read_plot3d, (dir / "plot3d_fortran_block_count_overflow.xyz").string());
    EXPECT_NE(what.find("plot3d_fortran_block_count_overflow.xyz: "), std::string::npos) << what;
    // Gmsh: a second $Nodes section wrote past the first one's tag table.
    what = test::input_error_of(read_gmsh_mesh, (dir / "gmsh_second_nodes_section.msh").string());
    EXPECT_NE(what.find("gmsh_second_nodes_section.msh:92: a second $Nodes section"),
              std::string::npos)
        << what;
    // A PLY point cloud with an element of 16 578 868 067 080 items and no property: the reader
    // looped over the items reading nothing (a timeout). The surface reader shares the header.
    what = test::input_error_of(read_point_cloud,
                                (dir / "points_ply_element_without_properties.ply").string());
    EXPECT_NE(what.find("PLY element 'v7rtex' declares 16578868067080 items but no property"),
              std::string::npos)
        << what;
    // Medit: an element count times its entries overflowed.
    what =
        test::input_error_of(read_medit_mesh, (dir / "medit_element_count_overflow.mesh").string());
    EXPECT_NE(what.find("elements do not fit in the file"), std::string::npos) << what;
}

// VTK XML files.
TEST(ReadErrors, FuzzFindingsInXmlVtkAreRefused) {
    const fs::path dir = fuzz_regressions();
    std::string what;
    // XML .vts: each crashed VTK 9.1's XML reader (a string array's byte count of 7e18, a
    // misspelt header_type, an unknown array type, string arrays holding fewer or more strings
    // than they declare or ending inside one, a piece extent running backwards, an element that
    // is no array among the arrays, appended data not starting with '_', points of one
    // component). Read now by the XML reader of our own: each refused with one line.
    for (const auto& [file, message] : std::vector<std::pair<std::string, std::string>>{
             {"vts_string_array_byte_count_garbage.vts",
              "array 'Points' of the points claims 7521983764484810083 bytes; at most 651 are "
              "left"},
             // header_type misspelt: the 4-byte headers then assumed read a byte count from the
             // middle of one.
             {"vts_header_type_misspelt.vts",
              "array 'Points' of the points claims 1885300067 bytes; at most 655 are left"},
             {"vts_unknown_array_type.vts",
              "array 'Points' of the points holds 0 values; expected 27 tuples of 3 components"},
             {"vts_string_array_with_fewer_strings.vts",
              "string array 'block_name' of the field data declares 2 x 1 values but holds 1"},
             {"vts_piece_extent_backwards.vts",
              "Piece Extent \"5 2 0 2 0 2\": a range runs backwards"},
             {"vts_string_array_unterminated.vts",
              "string array 'block_name' of the field data ends inside a string (no terminating "
              "zero)"},
             {"vts_string_array_with_more_strings.vts",
              "string array 'face_patch' of the field data declares 2 x 1 values but holds 6"},
             {"vts_field_data_holding_another_element.vts",
              "<FieldData> holds a <Arrtyyap> element; expected arrays only"},
             {"vts_appended_data_not_starting_with_underscore.vts",
              "its AppendedData does not start with '_' after the tag"},
             {"vts_points_without_their_component_count.vts",
              "the points array 'Points' has 1 components; expected 3"}}) {
        what = test::input_error_of(read_vtk_block_grid, (dir / file).string());
        EXPECT_NE(what.find(file + ": " + message), std::string::npos) << what;
        what = test::input_error_of(read_vtk_mesh, (dir / file).string());
        EXPECT_NE(what.find(message), std::string::npos) << what;
    }
}

// A valid grid's .vts with its cell array declared one value short: refused naming the array,
// where VTK would copy past the array's end.
TEST(ReadErrors, AVtsCellArrayShorterThanItsPieceIsRefused) {
    const BlockGrid grid = small_o_h_grid(2, 1);
    BlockGrid one;
    one.points = grid.points;
    one.kinds = grid.kinds;
    one.blocks = {grid.blocks[0]};
    const fs::path dir = scratch("short_array");
    const fs::path file = dir / "grid.vts";
    write_vtk_grid(one, file.string());
    EXPECT_EQ(read_vtk_block_grid(file.string()).num_cells(), one.num_cells());
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    // The scaled_jacobian array's byte count (8-byte header) made 8 bytes smaller.
    const size_t tag = bytes.find("Name=\"scaled_jacobian\"");
    ASSERT_NE(tag, std::string::npos);
    const size_t at = bytes.find("offset=\"", tag) + 8;
    const size_t offset = std::stoull(bytes.substr(at));
    const size_t data = bytes.find('_', bytes.find("<AppendedData")) + 1;
    std::uint64_t count = 0;
    std::memcpy(&count, &bytes[data + offset], 8);
    count -= 8;
    std::memcpy(&bytes[data + offset], &count, 8);
    std::ofstream(file, std::ios::binary) << bytes;
    const std::string what = test::input_error_of(read_vtk_block_grid, file.string());
    EXPECT_NE(what.find(fmt::format("array 'scaled_jacobian' of the cell data holds {} values; "
                                    "expected {} tuples of 1 components",
                                    count / 8, one.num_cells())),
              std::string::npos)
        << what;
}

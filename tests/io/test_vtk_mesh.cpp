#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkStructuredGridWriter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLStructuredGridWriter.h>

#include <filesystem>
#include <fstream>

#include "io/case_file.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"
#include "surface/analytic.h"
#include "tests/io/scratch_files.h"
#include "tests/io/vtk_test_grids.h"
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
    std::string text =
        "# vtk DataFile Version 3.0\none hex\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n";
    for (int c = 0; c < 8; ++c) text += fmt::format("{} {} {}\n", c & 1, (c >> 1) & 1, c >> 2);
    return text + fmt::format("CELLS 1 {}\n{}\nCELL_TYPES 1\n12\n", row_size, cell_row);
}

}  // namespace

TEST(VtkMesh, CellsWithPointIdsOutOfRangeOrTooFewAreRefusedNamingTheCell) {
    const fs::path dir = temp_dir("bad_ids");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {one_hex_vtk("8 0 1 3 2 4 5 7 99", 9),
         "cell 0 refers to point 99, but the file has points 0 to 7"},
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

TEST(VtkMesh, LegacyCellListsThatDisagreeWithTheirDeclaredSizeAreRefused) {
    // VTK's own legacy reader corrupted the heap on such lists ("free(): invalid next size").
    const fs::path dir = temp_dir("cell_lists");
    const std::vector<std::pair<std::string, std::string>> ascii = {
        {one_hex_vtk("8 0 1 3 2 4 5 7 6", 5),
         "CELLS: row 0 has 8 ids, beyond the 5 values the line declares"},
        {one_hex_vtk("8 0 1 3 2 4 5 7 6", 12),
         "CELLS: its 1 rows hold 9 values, but the line declares 12"},
        {one_hex_vtk("12 0 1 3 2 4 5 7 6", 9), "CELLS: row 0 has 12 ids, beyond the 9 values"},
    };
    int n = 0;
    for (const auto& [text, message] : ascii) {
        const std::string path = (dir / fmt::format("rows{}.vtk", n++)).string();
        std::ofstream(path) << text;
        for (const std::string& what : {test::input_error_of(read_vtk_mesh, path),
                                        test::input_error_of(read_volume_mesh, path)}) {
            EXPECT_NE(what.find(path + ":15: " + message), std::string::npos) << what;
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
    EXPECT_NE(what.find(mutated + ": byte "), std::string::npos) << what;
    EXPECT_NE(what.find(": CELLS: offset 2 is 16, outside [8, 15]"), std::string::npos) << what;
}

namespace {

// `data` written by VTK's own legacy writer (an independent producer of the format) in ASCII
// and binary, as versions 4.2 (cell rows) and 5.1 (offsets and connectivity).
template <class Writer>
std::vector<std::string> write_with_vtk(vtkDataObject* data, const fs::path& dir,
                                        const std::string& stem) {
    std::vector<std::string> files;
    for (const int version : {42, 51})
        for (const bool binary : {false, true}) {
            const std::string file =
                (dir / fmt::format("{}_{}_{}.vtk", stem, version, binary ? "binary" : "ascii"))
                    .string();
            vtkNew<Writer> writer;
            writer->SetFileName(file.c_str());
            writer->SetInputData(data);
            writer->SetFileVersion(version);
            if (binary)
                writer->SetFileTypeToBinary();
            else
                writer->SetFileTypeToASCII();
            EXPECT_EQ(writer->Write(), 1) << file;
            files.push_back(file);
        }
    return files;
}

// Arrays the readers skip, of each kind the writer has: point scalars and vectors, cell
// scalars, and field data with a string array (names with a space are written escaped).
void add_arrays_to_skip(vtkDataSet* data) {
    vtkNew<vtkDoubleArray> pressure;
    pressure->SetName("pressure");
    vtkNew<vtkFloatArray> velocity;
    velocity->SetName("velocity");
    velocity->SetNumberOfComponents(3);
    for (vtkIdType m = 0; m < data->GetNumberOfPoints(); ++m) {
        pressure->InsertNextValue(0.5 * double(m));
        velocity->InsertNextTuple3(double(m), 1, -2);
    }
    data->GetPointData()->SetScalars(pressure);
    data->GetPointData()->SetVectors(velocity);
    vtkNew<vtkIntArray> ids;
    ids->SetName("cell id");
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) ids->InsertNextValue(int(c));
    data->GetCellData()->SetScalars(ids);
    vtkNew<vtkStringArray> names;
    names->SetName("block_name");
    names->InsertNextValue("inlet block");
    names->InsertNextValue("");
    data->GetFieldData()->AddArray(names);
}

}  // namespace

TEST(LegacyVtk, VtkWrittenAsciiAndBinaryOldAndNewLayoutsReadToTheSameVolumeMesh) {
    // Two hexahedra, a tetrahedron on top and a boundary triangle; "fixed" on every third point.
    VolumeMesh expected;
    for (int c = 0; c < 12; ++c)
        expected.points.emplace_back(0.25 * (c & 1), (c >> 1) & 1, 1.5 * (c >> 2));
    expected.points.emplace_back(0.5, 0.25, 4.0);
    expected.hexes = {0, 1, 3, 2, 4, 5, 7, 6, 4, 5, 7, 6, 8, 9, 11, 10};
    expected.tets = {8, 9, 10, 12};
    for (size_t m = 0; m < expected.points.size(); ++m) expected.fixed.push_back(m % 3 == 0);
    const vtkSmartPointer<vtkUnstructuredGrid> grid =
        test::two_hexes_a_tet_and_a_triangle(VTK_DOUBLE);
    add_arrays_to_skip(grid);
    vtkNew<vtkUnsignedCharArray> fixed;  // written as a FIELD array among the point data
    fixed->SetName("fixed");
    for (uint8_t f : expected.fixed) fixed->InsertNextValue(f);
    grid->GetPointData()->AddArray(fixed);

    const std::vector<std::string> files =
        write_with_vtk<vtkUnstructuredGridWriter>(grid, temp_dir("legacy_ug"), "ug");
    for (const std::string& file : files) {
        const VolumeMesh mesh = read_volume_mesh(file);
        EXPECT_EQ(mesh.points, expected.points) << file;
        EXPECT_EQ(mesh.hexes, expected.hexes) << file;
        EXPECT_EQ(mesh.tets, expected.tets) << file;
        EXPECT_EQ(mesh.fixed, expected.fixed) << file;
    }
    // The layouts are the ones asked for: rows in 4.2, offsets in 5.1.
    std::ifstream old_layout(files[0]), new_layout(files[2]);
    const std::string old_text((std::istreambuf_iterator<char>(old_layout)), {});
    const std::string new_text((std::istreambuf_iterator<char>(new_layout)), {});
    EXPECT_NE(old_text.find("CELLS 4 27\n8 0 1 3 2"), std::string::npos) << old_text;
    EXPECT_NE(new_text.find("OFFSETS vtktypeint64"), std::string::npos) << new_text;
}

TEST(LegacyVtk, VtkWrittenStructuredGridsReadAsTheirXmlTwin) {
    // A 4 x 3 x 2 node grid with uneven spacing, through both mesh readers; the same grid as
    // .vts (VTK's XML writer and reader) gives the reference.
    auto grid = vtkSmartPointer<vtkStructuredGrid>::New();
    grid->SetDimensions(4, 3, 2);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i)
                points->InsertNextPoint(i * i * 0.5, j + 0.125 * i, 2.0 * k);
    grid->SetPoints(points);
    add_arrays_to_skip(grid);
    const fs::path dir = temp_dir("legacy_sg");
    const std::string xml = (dir / "sg.vts").string();
    vtkNew<vtkXMLStructuredGridWriter> writer;
    writer->SetFileName(xml.c_str());
    writer->SetInputData(grid);
    ASSERT_EQ(writer->Write(), 1);
    const HexMesh expected = read_vtk_mesh(xml);
    ASSERT_EQ(expected.num_cells(), 6);
    for (const std::string& file : write_with_vtk<vtkStructuredGridWriter>(grid, dir, "sg")) {
        const HexMesh mesh = read_vtk_mesh(file);
        EXPECT_EQ(mesh.points, expected.points) << file;
        EXPECT_EQ(mesh.hexes, expected.hexes) << file;
        const VolumeMesh volume = read_volume_mesh(file);
        EXPECT_EQ(volume.num_hexes(), 6) << file;
        EXPECT_TRUE(volume.fixed.empty()) << file;
    }
}

TEST(LegacyVtk, MalformedFilesAreRefusedNamingTheLineOrByteAndTheFault) {
    const fs::path dir = temp_dir("legacy_refusals");
    const std::string head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n";
    std::string cube = "POINTS 8 float\n";
    for (int c = 0; c < 8; ++c) cube += fmt::format("{} {} {}\n", c & 1, (c >> 1) & 1, c >> 2);
    const std::string cell = "CELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 1\n12\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {head + "POINTS 1000000000 float\n0 0 0\n",
         ":5: POINTS: 3000000000 values do not fit in the 7 bytes left"},
        {head + "POINTS 2 double\n0 0 0\n1 nan 0\n", ":7: point 1 has a non-finite coordinate"},
        {head + cube + "CELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 1\n99\n",
         ":17: CELL_TYPES: cell 0 has type 99, which VTK does not know"},
        {head + cube + "CELLS 1 9\n8 0 1 3 2 4 5 7 6\nCELL_TYPES 2\n12 12\n",
         "CELL_TYPES: 2 types for the 1 cells of CELLS"},
        {head + cube + cell + "POINT_DATA 7\n", ":18: POINT_DATA 7: the data set has 8 points"},
        {head + cube + cell + "CELL_DATA 1\nSCALARS p complex\nLOOKUP_TABLE default\n1\n",
         ":20: array 'p' has type 'complex', which VTK does not know"},
        {head + cube + cell + "POINT_DATA 8\nFIELD f 1\nfixed 1 7 int\n0 0 0 0 0 0 0\n",
         ":20: the point array \"fixed\" has 7 values for 8 points"},
        {head + cube + cell + "POINT_DATA 8\nSCALARS s float\nLOOKUP_TABLE default\n1 2 3\n",
         ":20: array 's': 8 values do not fit in the 7 bytes left in the file"},
        {head + cube + "CELLS 1 9\n8 0 1 3 2 4 5 7 6\n", "CELLS without CELL_TYPES"},
        {head + cube + cell + "POINT_DATA 8\nVECTOR v float\n",
         ":19: unknown keyword 'VECTOR' in the POINT_DATA section"},
        {head + cube + cell + "POINTS 8 float\n", ":18: a second POINTS section"},
        {"# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 2 2 3\n" + cube,
         "DIMENSIONS 2 2 3 do not make the 8 points of POINTS"},
        {"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n",
         ":4: a POLYDATA data set; volume meshes are read from"},
        {"# vtk DataFile Version 6.0\nt\nASCII\n",
         ":1: version 6.0: this reader knows versions 1.0 to 5.1"},
        {"# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n" + cube +
             "CELLS 1 9\nOFFSETS vtktypeint64\n0 8\nCONNECTIVITY vtktypeint64\n0 1 3 2 4 5 7 6\n",
         ":14: CELLS: OFFSETS instead of rows in a file of version 4.2"},
    };
    int n = 0;
    for (const auto& [text, message] : cases) {
        const std::string path = (dir / fmt::format("bad{}.vtk", n++)).string();
        std::ofstream(path, std::ios::binary) << text;
        for (const std::string& what : {test::input_error_of(read_vtk_mesh, path),
                                        test::input_error_of(read_volume_mesh, path)}) {
            EXPECT_NE(what.find(path + ":"), std::string::npos) << what;
            EXPECT_NE(what.find(message), std::string::npos) << what;
        }
    }
    // Binary: a count beyond the file and a string of a field array running past its end are
    // refused naming the byte.
    const std::string binary_head =
        "# vtk DataFile Version 5.1\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
    const std::string big = (dir / "big.vtk").string();
    std::ofstream(big, std::ios::binary) << binary_head << "POINTS 100 double\n"
                                         << std::string(24, '\0');
    std::string what = test::input_error_of(read_volume_mesh, big);
    EXPECT_NE(
        what.find(big +
                  ": byte 80: POINTS: 300 values do not fit in the 24 bytes left in the file"),
        std::string::npos)
        << what;
    const std::string strings = (dir / "strings.vtk").string();
    std::ofstream(strings, std::ios::binary) << binary_head
                                             << "FIELD FieldData 1\nname 1 1 string\n\xc5"
                                                "abc";
    what = test::input_error_of(read_volume_mesh, strings);
    EXPECT_NE(what.find("array 'name': string 0 of 5 bytes runs past the end of the file"),
              std::string::npos)
        << what;
}

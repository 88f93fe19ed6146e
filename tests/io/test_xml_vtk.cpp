// The VTK XML reader of our own (io/xml_vtk.h): every layout VTK's writers make reads back to
// the data set written, and broken files are refused naming the fault.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLMultiBlockDataWriter.h>
#include <vtkXMLStructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>
#include <fstream>

#include "io/case_file.h"
#include "io/vtk_mesh.h"
#include "io/xml_vtk.h"
#include "tests/io/scratch_files.h"
#include "tests/io/vtk_test_grids.h"

using namespace hexmesh;
namespace fs = std::filesystem;

namespace {

class XmlVtk : public test::ScratchFiles {
  protected:
    XmlVtk() : ScratchFiles("hexmesh_test_xml_vtk_") {}
};

// Point, cell and field arrays of several types, strings with an empty one and markup in them.
void add_arrays(vtkDataSet* data) {
    vtkNew<vtkUnsignedCharArray> kinds;
    kinds->SetName("vertex_kind");
    for (vtkIdType m = 0; m < data->GetNumberOfPoints(); ++m)
        kinds->InsertNextValue(static_cast<unsigned char>(m % 5));
    data->GetPointData()->AddArray(kinds);
    vtkNew<vtkIntArray> pairs;
    pairs->SetName("pairs");
    pairs->SetNumberOfComponents(2);
    for (vtkIdType m = 0; m < data->GetNumberOfPoints(); ++m) {
        pairs->InsertNextValue(int(-7 * m));
        pairs->InsertNextValue(int(100000 * m));
    }
    data->GetPointData()->AddArray(pairs);
    vtkNew<vtkDoubleArray> sj;
    sj->SetName("scaled_jacobian");
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
        sj->InsertNextValue(1.0 - 0.125 * double(c));
    data->GetCellData()->AddArray(sj);
    vtkNew<vtkStringArray> names;
    names->SetName("face_patch");
    for (const char* s : {"wall", "", "far <field> & \"inlet\"", "x"}) names->InsertNextValue(s);
    data->GetFieldData()->AddArray(names);
}

// Each array of `want` is in `got` with the same components and values.
void expect_same_arrays(vtkFieldData* want, vtkFieldData* got, const std::string& where) {
    ASSERT_EQ(got->GetNumberOfArrays(), want->GetNumberOfArrays()) << where;
    for (int a = 0; a < want->GetNumberOfArrays(); ++a) {
        vtkAbstractArray* w = want->GetAbstractArray(a);
        vtkAbstractArray* g = got->GetAbstractArray(w->GetName());
        ASSERT_NE(g, nullptr) << where << " " << w->GetName();
        ASSERT_EQ(g->GetNumberOfComponents(), w->GetNumberOfComponents())
            << where << " " << w->GetName();
        ASSERT_EQ(g->GetNumberOfValues(), w->GetNumberOfValues()) << where << " " << w->GetName();
        if (auto* ws = vtkStringArray::SafeDownCast(w)) {
            auto* gs = vtkStringArray::SafeDownCast(g);
            ASSERT_NE(gs, nullptr) << where;
            for (vtkIdType k = 0; k < ws->GetNumberOfValues(); ++k)
                EXPECT_EQ(gs->GetValue(k), ws->GetValue(k)) << where;
            continue;
        }
        auto* wd = vtkDataArray::SafeDownCast(w);
        auto* gd = vtkDataArray::SafeDownCast(g);
        ASSERT_NE(gd, nullptr) << where;
        EXPECT_EQ(gd->GetDataTypeSize(), wd->GetDataTypeSize()) << where << " " << w->GetName();
        for (vtkIdType t = 0; t < wd->GetNumberOfTuples(); ++t)
            for (int c = 0; c < wd->GetNumberOfComponents(); ++c)
                EXPECT_EQ(gd->GetComponent(t, c), wd->GetComponent(t, c))
                    << where << " " << w->GetName() << " " << t;
    }
}

void expect_same_points(vtkDataSet* want, vtkDataSet* got, const std::string& where) {
    ASSERT_EQ(got->GetNumberOfPoints(), want->GetNumberOfPoints()) << where;
    for (vtkIdType m = 0; m < want->GetNumberOfPoints(); ++m) {
        double w[3], g[3];
        want->GetPoint(m, w);
        got->GetPoint(m, g);
        for (int a = 0; a < 3; ++a) EXPECT_EQ(g[a], w[a]) << where << " point " << m;
    }
    expect_same_arrays(want->GetPointData(), got->GetPointData(), where + " point data");
    expect_same_arrays(want->GetCellData(), got->GetCellData(), where + " cell data");
    expect_same_arrays(want->GetFieldData(), got->GetFieldData(), where + " field data");
}

// Writes `data` with VTK's writer in every layout: ascii; inline base64; appended raw and base64;
// each binary one uncompressed and compressed three ways in small blocks (a partial last one);
// 4- and 8-byte headers; both byte orders. Returns the files.
template <class Writer>
std::vector<std::string> write_every_layout(vtkDataObject* data, const fs::path& dir,
                                            const std::string& ext) {
    std::vector<std::string> files;
    const auto write = [&](const std::string& name, auto configure) {
        const std::string file = (dir / (name + ext)).string();
        vtkNew<Writer> writer;
        writer->SetFileName(file.c_str());
        writer->SetInputData(data);
        configure(*writer);
        EXPECT_EQ(writer->Write(), 1) << file;
        files.push_back(file);
    };
    write("ascii", [](Writer& w) { w.SetDataModeToAscii(); });
    for (const char* mode : {"binary", "raw", "base64"})
        for (const char* compressor : {"none", "zlib", "lz4", "lzma"})
            for (int header : {32, 64})
                for (const char* order : {"le", "be"})
                    write(fmt::format("{}_{}_{}_{}", mode, compressor, header, order),
                          [&](Writer& w) {
                              if (std::string(mode) == "binary") {
                                  w.SetDataModeToBinary();
                              } else {
                                  w.SetDataModeToAppended();
                                  w.SetEncodeAppendedData(std::string(mode) == "base64");
                              }
                              const std::string c = compressor;
                              if (c == "none") w.SetCompressorTypeToNone();
                              if (c == "zlib") w.SetCompressorTypeToZLib();
                              if (c == "lz4") w.SetCompressorTypeToLZ4();
                              if (c == "lzma") w.SetCompressorTypeToLZMA();
                              w.SetBlockSize(40);  // several blocks an array, the last one partial
                              if (header == 32)
                                  w.SetHeaderTypeToUInt32();
                              else
                                  w.SetHeaderTypeToUInt64();
                              if (std::string(order) == "le")
                                  w.SetByteOrderToLittleEndian();
                              else
                                  w.SetByteOrderToBigEndian();
                          });
    return files;
}

vtkSmartPointer<vtkStructuredGrid> small_structured_grid() {
    auto grid = vtkSmartPointer<vtkStructuredGrid>::New();
    grid->SetDimensions(4, 3, 2);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i)
                points->InsertNextPoint(i * i * 0.5, j + 0.125 * i, -2.0 * k);
    grid->SetPoints(points);
    add_arrays(grid);
    return grid;
}

}  // namespace

TEST_F(XmlVtk, EveryLayoutOfAStructuredGridReadsBackToTheGridWritten) {
    const vtkSmartPointer<vtkStructuredGrid> grid = small_structured_grid();
    const std::vector<std::string> files =
        write_every_layout<vtkXMLStructuredGridWriter>(grid, dir_, ".vts");
    ASSERT_EQ(files.size(), 49u);
    for (const std::string& file : files) {
        const vtkSmartPointer<vtkDataObject> read = read_xml_vtk(file);
        auto* back = vtkStructuredGrid::SafeDownCast(read);
        ASSERT_NE(back, nullptr) << file;
        int dims[3];
        back->GetDimensions(dims);
        EXPECT_EQ(dims[0], 4);
        EXPECT_EQ(dims[1], 3);
        EXPECT_EQ(dims[2], 2);
        expect_same_points(grid, back, file);
    }
}

TEST_F(XmlVtk, EveryLayoutOfAnUnstructuredGridReadsBackToTheCellsWritten) {
    const vtkSmartPointer<vtkUnstructuredGrid> grid =
        test::two_hexes_a_tet_and_a_triangle(VTK_FLOAT);
    add_arrays(grid);
    for (const std::string& file :
         write_every_layout<vtkXMLUnstructuredGridWriter>(grid, dir_, ".vtu")) {
        const vtkSmartPointer<vtkDataObject> read = read_xml_vtk(file);
        auto* back = vtkUnstructuredGrid::SafeDownCast(read);
        ASSERT_NE(back, nullptr) << file;
        ASSERT_EQ(back->GetNumberOfCells(), 4) << file;
        for (vtkIdType c = 0; c < 4; ++c) {
            EXPECT_EQ(back->GetCellType(c), grid->GetCellType(c)) << file;
            vtkNew<vtkIdList> want, got;
            grid->GetCellPoints(c, want);
            back->GetCellPoints(c, got);
            ASSERT_EQ(got->GetNumberOfIds(), want->GetNumberOfIds()) << file;
            for (vtkIdType k = 0; k < want->GetNumberOfIds(); ++k)
                EXPECT_EQ(got->GetId(k), want->GetId(k)) << file;
        }
        expect_same_points(grid, back, file);
    }
}

TEST_F(XmlVtk, AMultiblockFileOfNestedBlocksReadsAsItsNamedPiecesInOrder) {
    auto inner = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    inner->SetBlock(0, small_structured_grid());
    inner->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "inner & first");
    inner->SetBlock(1, nullptr);  // an empty block
    inner->SetBlock(2, small_structured_grid());
    inner->GetMetaData(2u)->Set(vtkCompositeDataSet::NAME(), "inner second");
    auto outer = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    outer->SetBlock(0, small_structured_grid());
    outer->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "top");
    outer->SetBlock(1, inner);
    const std::string file = path("nested.vtm");
    vtkNew<vtkXMLMultiBlockDataWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputData(outer);
    ASSERT_EQ(writer->Write(), 1);
    const vtkSmartPointer<vtkDataObject> read = read_xml_vtk(file);
    auto* back = vtkMultiBlockDataSet::SafeDownCast(read);
    ASSERT_NE(back, nullptr);
    ASSERT_EQ(back->GetNumberOfBlocks(), 3u);
    const char* names[] = {"top", "inner & first", "inner second"};
    for (unsigned b = 0; b < 3; ++b) {
        EXPECT_STREQ(back->GetMetaData(b)->Get(vtkCompositeDataSet::NAME()), names[b]);
        auto* piece = vtkStructuredGrid::SafeDownCast(back->GetBlock(b));
        ASSERT_NE(piece, nullptr);
        expect_same_points(small_structured_grid(), piece, names[b]);
    }
}

namespace {

const std::string kCubePoints = "0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1";

// A .vts of one cell (2 x 2 x 2 points, inline ascii): `more` inside its piece, `points` its
// points' DataArray text.
std::string one_cell_vts(const std::string& more = "", const std::string& root_attributes = "",
                         const std::string& points = kCubePoints) {
    return fmt::format(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"StructuredGrid\" version=\"0.1\"{}>\n"
        "<StructuredGrid WholeExtent=\"0 1 0 1 0 1\">\n<Piece Extent=\"0 1 0 1 0 1\">\n{}"
        "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
        "format=\"ascii\">{}</DataArray></Points>\n"
        "</Piece>\n</StructuredGrid>\n</VTKFile>\n",
        root_attributes, more, points);
}

// A .vtu of one hexahedron, its cell arrays' texts given.
std::string one_hex_vtu(const std::string& connectivity, const std::string& offsets,
                        const std::string& types) {
    return fmt::format(
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"8\" "
        "NumberOfCells=\"1\">"
        "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
        "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1</DataArray></Points><Cells>"
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">{}</DataArray>"
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">{}</DataArray>"
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">{}</DataArray>"
        "</Cells></Piece></UnstructuredGrid></VTKFile>",
        connectivity, offsets, types);
}

// A StructuredGrid piece of one point, for files whose fault lies elsewhere.
const std::string one_point_piece =
    "<Piece Extent=\"0 0 0 0 0 0\"><Points><DataArray type=\"Float32\" "
    "NumberOfComponents=\"3\" format=\"ascii\">0 0 0</DataArray></Points></Piece>";

// Each file is refused by read_vtk_mesh with a message naming it and holding its fault.
void expect_refused(const std::vector<std::pair<std::string, std::string>>& cases) {
    for (const auto& [file, message] : cases) {
        const std::string what = test::input_error_of(read_vtk_mesh, file);
        EXPECT_NE(what.find(file), std::string::npos) << what;
        EXPECT_NE(what.find(message), std::string::npos) << file << ": " << what;
    }
}

}  // namespace

TEST_F(XmlVtk, SmallGoodFilesRead) {
    EXPECT_EQ(read_vtk_mesh(write("good.vts", one_cell_vts())).num_cells(), 1);
    EXPECT_EQ(
        read_vtk_mesh(write("good.vtu", one_hex_vtu("0 1 2 3 4 5 6 7", "8", "12"))).num_cells(), 1);
}

// XML that is not well formed, nested too deep or with too many attributes, and files of
// another type: refused naming the fault.
TEST_F(XmlVtk, MalformedXmlIsRefused) {
    std::string deep;
    for (int k = 0; k < 100000; ++k) deep += "<a>";
    expect_refused({
        {write("deep.vts", "<VTKFile type=\"StructuredGrid\">" + deep),
         "elements nested more than 64 deep"},
        {write("unclosed.vts", "<VTKFile type=\"StructuredGrid\"><StructuredGrid>"),
         "the file ends inside <StructuredGrid>"},
        {write("mismatch.vts", "<VTKFile><A></B></VTKFile>"), ":1: </B> closes <A>"},
        {write("not_xml.vts", "solid cube\n"), "text outside the <VTKFile> element"},
        {write("entity.vts", "<VTKFile type=\"&bogus;\"/>"), "unknown entity &bogus;"},
        {write(
             "attributes.vts", "<VTKFile" +
                                   [] {
                                       std::string a;
                                       for (int k = 0; k < 65; ++k)
                                           a += fmt::format(" a{}=\"\"", k);
                                       return a;
                                   }() +
                                   "/>"),
         "<VTKFile: more than 64 attributes"},
        {write("polydata.vtp.vts", "<VTKFile type=\"PolyData\"/>"),
         "a VTK XML file of type \"PolyData\""},
    });
}

// Settings of <VTKFile> it does not know, and arrays whose type, components, count or
// values are wrong: refused naming the fault.
TEST_F(XmlVtk, BadSettingsAndValuesAreRefused) {
    expect_refused({
        {write("header.vts", one_cell_vts("", " header_type=\"UInt16\"")),
         "header_type is \"UInt16\"; expected UInt32 or UInt64"},
        {write("compressor.vts", one_cell_vts("", " compressor=\"vtkZStd\"")),
         "compressor \"vtkZStd\""},
        {write("nan.vts",
               one_cell_vts("", "", "0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 nan 1")),
         "point 7 has a non-finite coordinate"},
        {write("short.vts", one_cell_vts("", "", "0 0 0 1 0 0")),
         "array '' of the points holds 6 values; expected 8 tuples of 3 components"},
        {write("word.vts", one_cell_vts("", "", "0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 x 1")),
         "value 22 is \"x\", not a number"},
        {write("bit.vts", one_cell_vts("<CellData><DataArray type=\"Bit\" Name=\"b\" "
                                       "format=\"ascii\">1</DataArray></CellData>")),
         "array 'b' of the cell data has type \"Bit\""},
        {write("components.vts",
               one_cell_vts("<CellData><DataArray type=\"Int32\" Name=\"c\" "
                            "NumberOfComponents=\"0\" format=\"ascii\">1</DataArray></CellData>")),
         "array 'c' of the cell data has NumberOfComponents \"0\""},
        {write("range.vts", one_cell_vts("<CellData><DataArray type=\"UInt8\" Name=\"c\" "
                                         "format=\"ascii\">300</DataArray></CellData>")),
         "array 'c' of the cell data: value 0 is \"300\", not a integer in the array's range"},
        {write("control.vts", one_cell_vts("<CellData><DataArray type=\"Int32\x01\" Name=\"c\" "
                                           "format=\"ascii\">1</DataArray></CellData>")),
         "array 'c' of the cell data has type \"Int32\\x01\""},
        {write("strings.vts",
               "<VTKFile type=\"StructuredGrid\"><StructuredGrid WholeExtent=\"0 0 0 0 0 "
               "0\"><FieldData>"
               "<Array type=\"String\" Name=\"s\" format=\"ascii\">97 0</Array></FieldData>" +
                   one_point_piece + "</StructuredGrid></VTKFile>"),
         "string array 's' of the field data does not declare its NumberOfTuples"},
    });
}

// Binary data that do not decode, claim more bytes than are left or than their compressed
// blocks can give, or share their appended bytes: refused naming the fault.
TEST_F(XmlVtk, BrokenBinaryDataIsRefused) {
    expect_refused({
        {write("base64.vts",
               one_cell_vts("<PointData><DataArray type=\"UInt8\" Name=\"k\" "
                            "format=\"binary\">CAAA*AABAgMEBQYH</DataArray></PointData>")),
         "array 'k' of the point data: its base64 text holds '*'"},
        {write("bytes.vts",
               one_cell_vts("<PointData><DataArray type=\"UInt8\" Name=\"k\" "
                            "format=\"binary\">/wAAAAABAgMEBQYH</DataArray></PointData>")),
         "array 'k' of the point data claims 255 bytes; at most 11 are left"},
        {write("no_appended.vts", one_cell_vts("<PointData><DataArray type=\"UInt8\" Name=\"k\" "
                                               "format=\"appended\" offset=\"0\"/></PointData>")),
         "array 'k' of the point data is appended, but the file has no <AppendedData>"},
        // A block table claiming 3 GiB from a 10-byte block: refused before anything is sized.
        {write("inflated.vts",
               one_cell_vts("<PointData><DataArray type=\"UInt8\" Name=\"k\" format=\"binary\">"
                            "AQAAAAAAAAAAAADAAAAAAAAAAAAAAAAACgAAAAAAAAA=MDEyMzQ1Njc4OQ==</"
                            "DataArray></PointData>",
                            " header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"")),
         "array 'k' of the point data: compressed block 0 of 10 bytes claims 3221225472 bytes, "
         "more than "
         "vtkZLibDataCompressor can give"},
        // Two arrays reading the same appended bytes.
        {write("shared.vts",
               "<VTKFile type=\"StructuredGrid\" header_type=\"UInt32\"><StructuredGrid "
               "WholeExtent=\"0 0 0 0 0 0\">"
               "<FieldData><Array type=\"UInt8\" Name=\"a\" format=\"appended\" offset=\"0\"/>"
               "<Array type=\"UInt8\" Name=\"b\" format=\"appended\" offset=\"0\"/></FieldData>" +
                   one_point_piece + "</StructuredGrid><AppendedData encoding=\"raw\">_" +
                   std::string("\x02\0\0\0xy", 6) + "</AppendedData></VTKFile>"),
         "array 'b' of the field data shares its appended bytes with another array"},
    });
}

// Pieces, extents, cell lists and multiblock pieces that do not add up: refused naming the
// fault.
TEST_F(XmlVtk, BrokenDataSetsAreRefused) {
    expect_refused({
        {write("two_pieces.vts",
               "<VTKFile type=\"StructuredGrid\"><StructuredGrid WholeExtent=\"0 1 0 1 0 "
               "1\"><Piece Extent=\"0 1 0 1 0 1\"/>"
               "<Piece Extent=\"0 1 0 1 0 1\"/></StructuredGrid></VTKFile>"),
         "its <StructuredGrid> holds 2 pieces; this reader reads files of one piece"},
        {write("huge.vts",
               "<VTKFile type=\"StructuredGrid\"><StructuredGrid WholeExtent=\"0 2000000000 0 "
               "2000000000 0 2000000000\">"
               "<Piece Extent=\"0 2000000000 0 2000000000 0 "
               "2000000000\"/></StructuredGrid></VTKFile>"),
         "its Piece Extent makes more points than a grid holds"},
        {write(
             "extent.vts",
             "<VTKFile type=\"StructuredGrid\"><StructuredGrid WholeExtent=\"-5000000000000000000 "
             "5000000000000000000 0 0 0 0\"><Piece Extent=\"0 0 0 0 0 "
             "0\"/></StructuredGrid></VTKFile>"),
         "WholeExtent \"-5000000000000000000 5000000000000000000...\": a range beyond what a grid "
         "holds"},
        {write("id.vtu", one_hex_vtu("0 1 2 3 4 5 6 8", "8", "12")),
         "cell 0 refers to point 8, but the file has points 0 to 7"},
        {write("offsets.vtu", one_hex_vtu("0 1 2 3 4 5 6 7", "9", "12")),
         "the cells' offsets: cell 0 ends at 9"},
        {write("offsets_short.vtu", one_hex_vtu("0 1 2 3 4 5 6 7", "7", "12")),
         "the cells' offsets end at 7; the connectivity holds 8 ids"},
        {write("type.vtu", one_hex_vtu("0 1 2 3 4 5 6 7", "8", "99")),
         "cell 0 has type 99, which VTK does not know"},
        {write("polyhedron.vtu", one_hex_vtu("0 1 2 3 4 5 6 7", "8", "42")),
         "cell 0 is a polyhedron (42), which is not read"},
        {write("self.vtm",
               "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet "
               "file=\"self.vts\"/></vtkMultiBlockDataSet></VTKFile>"),
         "its piece 'self.vts' does not exist"},
        {write("loop.vtm",
               "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet "
               "file=\"loop.vtm\"/></vtkMultiBlockDataSet></VTKFile>"),
         "its piece 'loop.vtm' is a '.vtm' file; expected .vts or .vtu"},

    });
}

// Unnamed arrays are kept apart (as VTK's reader does), and a piece of no points may have an
// empty <Points> (as VTK writes an empty grid).
TEST_F(XmlVtk, UnnamedArraysAndEmptyPointsRead) {
    const std::string unnamed =
        write("unnamed.vts",
              one_cell_vts("<CellData><DataArray type=\"Int32\" format=\"ascii\">1</DataArray>"
                           "<DataArray type=\"Int32\" format=\"ascii\">2</DataArray></CellData>"));
    const vtkSmartPointer<vtkDataObject> two = read_xml_vtk(unnamed);
    EXPECT_EQ(vtkDataSet::SafeDownCast(two)->GetCellData()->GetNumberOfArrays(), 2);
    const std::string empty =
        write("empty.vtu",
              "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"0\" "
              "NumberOfCells=\"0\"><Points></Points><Cells></Cells></Piece></UnstructuredGrid></"
              "VTKFile>");
    EXPECT_EQ(vtkDataSet::SafeDownCast(read_xml_vtk(empty))->GetNumberOfPoints(), 0);
}

// A .vts that names itself a multiblock file, read as a piece: refused, not read forever.
TEST_F(XmlVtk, MultiblockFileAsItsOwnPieceIsRefused) {
    write("disguised.vts",
          "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet "
          "file=\"disguised.vts\"/>"
          "</vtkMultiBlockDataSet></VTKFile>");
    const std::string what = test::input_error_of(read_vtk_mesh, path("disguised.vts"));
    EXPECT_NE(what.find("a piece of a multiblock file that is a multiblock file itself"),
              std::string::npos)
        << what;
}

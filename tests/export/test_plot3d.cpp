#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkMultiBlockPLOT3DReader.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkStructuredGrid.h>

#include <fstream>
#include <map>

#include "export_test_support.h"
#include "io/export_grid.h"
#include "io/neutral_map.h"
#include "io/plot3d.h"
#include "io/vtk_mesh.h"
#include "tests/io/scratch_files.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

const Plot3dFormat variants[] = {
    {Plot3dEncoding::fortran, false},  {Plot3dEncoding::fortran, true},
    {Plot3dEncoding::c_binary, false}, {Plot3dEncoding::c_binary, true},
    {Plot3dEncoding::ascii, false},    {Plot3dEncoding::ascii, true},
};

std::string label(const Plot3dFormat& f) {
    const char* e = f.encoding == Plot3dEncoding::fortran    ? "fortran"
                    : f.encoding == Plot3dEncoding::c_binary ? "c"
                                                             : "ascii";
    return std::string(e) + (f.single_precision ? "-single" : "-double");
}

// The coordinate we expect back: the double itself, or its float rounding.
double stored(double x, bool single) {
    return single ? double(float(x)) : x;
}

// ASCII does not say its precision: a single-precision value reads back as the double
// nearest to its decimal text, which rounds to the same float.
double as_read(double x, const Plot3dFormat& f) {
    return f.single_precision && f.encoding == Plot3dEncoding::ascii ? double(float(x)) : x;
}

}  // namespace

TEST(Plot3d, EveryVariantReadsBackWithPatchesAndSharedNodes) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path dir = scratch("plot3d_ours");
    for (const Plot3dFormat& f : variants) {
        SCOPED_TRACE(label(f));
        const std::string file = (dir / (label(f) + ".xyz")).string();
        write_plot3d(grid, file, f);
        const Plot3dFormat detected = detect_plot3d_format(file);
        EXPECT_EQ(detected.encoding, f.encoding);
        if (f.encoding != Plot3dEncoding::ascii) {
            EXPECT_EQ(detected.single_precision, f.single_precision);
        }

        const BlockGrid back = read_plot3d(file);
        ASSERT_EQ(back.blocks.size(), grid.blocks.size());
        EXPECT_EQ(back.points.size(), grid.points.size());  // interface nodes merged again
        for (size_t b = 0; b < grid.blocks.size(); ++b) {
            const Block& want = grid.blocks[b];
            const Block& got = back.blocks[b];
            EXPECT_EQ(got.name, want.name);
            EXPECT_EQ(got.face_patch, want.face_patch);
            ASSERT_EQ(got.nodes.count(), want.nodes.count());
            for (Id m = 0; m < want.nodes.count(); ++m)
                for (int a = 0; a < 3; ++a)
                    ASSERT_EQ(as_read(back.points[got.node_ids[m]][a], f),
                              stored(grid.points[want.node_ids[m]][a], f.single_precision));
        }
    }
}

TEST(Plot3d, VtkReaderReadsEveryVariantBackToTheSameCoordinates) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path dir = scratch("plot3d_vtk");
    for (const Plot3dFormat& f : variants) {
        SCOPED_TRACE(label(f));
        const std::string file = (dir / (label(f) + ".xyz")).string();
        write_plot3d(grid, file, f);

        vtkNew<vtkMultiBlockPLOT3DReader> reader;
        reader->SetXYZFileName(file.c_str());
        reader->AutoDetectFormatOff();
        reader->SetBinaryFile(f.encoding != Plot3dEncoding::ascii);
        reader->SetHasByteCount(f.encoding == Plot3dEncoding::fortran);
        reader->SetMultiGrid(1);
        reader->SetIBlanking(0);
        reader->SetTwoDimensionalGeometry(0);
        reader->SetDoublePrecision(!f.single_precision);
        reader->SetByteOrderToLittleEndian();
        reader->Update();
        vtkMultiBlockDataSet* out = reader->GetOutput();
        ASSERT_NE(out, nullptr);
        ASSERT_EQ(out->GetNumberOfBlocks(), grid.blocks.size());
        for (unsigned b = 0; b < out->GetNumberOfBlocks(); ++b) {
            auto* sg = vtkStructuredGrid::SafeDownCast(out->GetBlock(b));
            ASSERT_NE(sg, nullptr) << b;
            const Block& want = grid.blocks[b];
            int dims[3];
            sg->GetDimensions(dims);
            EXPECT_EQ(dims[0], want.nodes.ni);
            EXPECT_EQ(dims[1], want.nodes.nj);
            EXPECT_EQ(dims[2], want.nodes.nk);
            ASSERT_EQ(sg->GetNumberOfPoints(), want.nodes.count());
            if (!f.single_precision) {
                EXPECT_EQ(sg->GetPoints()->GetDataType(), VTK_DOUBLE);
            }
            for (Id m = 0; m < want.nodes.count(); ++m) {
                double x[3];
                sg->GetPoint(m, x);
                for (int a = 0; a < 3; ++a)
                    ASSERT_EQ(x[a], stored(grid.points[want.node_ids[m]][a], f.single_precision))
                        << "block " << b << " node " << m;
            }
        }
    }
}

TEST(Plot3d, ExportFormatNamesChooseTheVariant) {
    const BlockGrid grid = small_o_h_grid(3, 2);
    const fs::path dir = scratch("plot3d_names");
    const std::pair<const char*, Plot3dFormat> names[] = {
        {"plot3d", {Plot3dEncoding::fortran, false}},
        {"plot3d-c-single", {Plot3dEncoding::c_binary, true}},
        {"plot3d-fortran-single", {Plot3dEncoding::fortran, true}},
        {"plot3d-ascii", {Plot3dEncoding::ascii, false}},
    };
    for (const auto& [name, want] : names) {
        SCOPED_TRACE(name);
        const std::string file = (dir / export_file_name(name, "grid", grid)).string();
        export_grid(grid, name, file);
        const Plot3dFormat got = detect_plot3d_format(file);
        EXPECT_EQ(got.encoding, want.encoding);
        if (want.encoding != Plot3dEncoding::ascii) {
            EXPECT_EQ(got.single_precision, want.single_precision);
        }
        EXPECT_TRUE(fs::exists(plot3d_patch_file(file)));
        EXPECT_EQ(read_vtk_mesh(file).num_cells(), grid.num_cells());  // `quality` reads it too
    }
}

namespace {

// Node of point (u, v) of a map face range.
Id range_node(const BlockGrid& grid, const NmfFaceRange& r, int u, int v) {
    const Block& b = grid.blocks[size_t(r.block - 1)];
    const std::array<int, 3> ijk =
        nmf_face_node({b.nodes.ni, b.nodes.nj, b.nodes.nk}, r.face, u, v);
    return b.node(ijk[0], ijk[1], ijk[2]);
}

// The neutral map file beside a Plot3D grid, as our reader reads it: every patched block face
// once with its type, every interface once, and every point of an interface's first face,
// carried to the second face by the entry's ranges and Swap as the format defines them, lands
// on the same grid point.
void expect_map_describes(const BlockGrid& grid, const fs::path& xyz) {
    const NeutralMap map = read_neutral_map(plot3d_map_file(xyz.string()));
    ASSERT_EQ(map.dims.size(), grid.blocks.size());
    std::map<std::pair<int, int>, std::string> patched, want;
    for (const NmfBoundary& b : map.boundaries) {
        EXPECT_TRUE(
            patched
                .emplace(std::pair{b.range.block - 1, nmf_face_to_block_face(b.range.face)}, b.type)
                .second);
    }
    int open_faces = 0;
    for (size_t b = 0; b < grid.blocks.size(); ++b)
        for (int f = 0; f < 6; ++f) {
            const std::string& p = grid.blocks[b].face_patch[f];
            if (p.empty())
                ++open_faces;
            else
                want[{int(b), f}] = p == "wall" ? "WALL" : p == "farfield" ? "FARFIELD" : p;
        }
    EXPECT_EQ(patched, want);
    EXPECT_EQ(2 * map.interfaces.size(),
              size_t(open_faces));  // each interface joins two open faces
    for (const NmfInterface& link : map.interfaces) {
        const NmfFaceRange &a = link.first, &b = link.second;
        const int step1 = b.e1 >= b.s1 ? 1 : -1, step2 = b.e2 >= b.s2 ? 1 : -1;
        for (int u = a.s1; u <= a.e1; ++u)
            for (int v = a.s2; v <= a.e2; ++v) {
                const int along_u = std::abs(u - a.s1), along_v = std::abs(v - a.s2);
                const int q1 = b.s1 + step1 * (link.swap ? along_v : along_u);
                const int q2 = b.s2 + step2 * (link.swap ? along_u : along_v);
                ASSERT_EQ(grid.points[range_node(grid, a, u, v)],
                          grid.points[range_node(grid, b, q1, q2)])
                    << "interface block " << a.block << " face " << a.face << " point " << u << ", "
                    << v;
            }
    }
}

}  // namespace

TEST(Plot3d, NeutralMapFileListsPatchesAndInterfacesThatMapPointOntoPoint) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions axis;  // 51 blocks: rings and frames meet in every orientation
    axis.cells_per_edge = 6;
    axis.wall_cells = 2;
    axis.axis = 2;
    for (const BlockGrid& grid :
         {small_o_h_grid(), small_o_grid(4, 3), make_o_h_grid(sphere, axis)}) {
        SCOPED_TRACE(grid.blocks.size());
        const fs::path xyz = scratch("nmf") / "grid.xyz";
        write_plot3d(grid, xyz.string(), Plot3dFormat{});
        expect_map_describes(grid, xyz);
        // Without the hexmesh side file the grid's patches come from the map.
        fs::remove(plot3d_patch_file(xyz.string()));
        const BlockGrid back = read_plot3d(xyz.string());
        ASSERT_EQ(back.blocks.size(), grid.blocks.size());
        for (size_t b = 0; b < grid.blocks.size(); ++b)
            EXPECT_EQ(back.blocks[b].face_patch, grid.blocks[b].face_patch) << b;
    }
}

TEST(Plot3d, MalformedNeutralMapFilesAreRefusedNamingTheLine) {
    const fs::path dir = scratch("nmf_bad");
    const std::string head = "# blocks\n1\n1 3 3 3\n";
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"2\n1 3 3 3\n", "ends before its 2 block sizes"},
        {head + "'WALL' 1 7 1 3 1 3\n", "line 4: the face is '7'; expected an integer in [1, 6]"},
        {head + "'WALL' 1 1 1 4 1 3\n", "line 4: E1 is '4'; expected an integer in [1, 3]"},
        {head + "'WALL' 1 1 1 3\n", "line 4: a boundary line ('WALL') has 7 fields"},
        {head + "'ONE_TO_ONE' 1 1 1 3 1 3 1 2 1 3 1 3 MAYBE\n", "line 4: Swap is 'MAYBE'"},
        {head + "'ONE_TO_ONE' 1 1 1 3 1 3 1 2 1 2 1 3 FALSE\n", "different sizes"},
        {"1\n1 3 x 3\n", "line 2: JDIM is 'x'"},
    };
    int n = 0;
    for (const auto& [text, message] : bad) {
        const std::string path = (dir / fmt::format("bad{}.nmf", n++)).string();
        std::ofstream(path) << text;
        const std::string what = test::input_error_of(read_neutral_map, path);
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(message), std::string::npos) << what;
    }
}

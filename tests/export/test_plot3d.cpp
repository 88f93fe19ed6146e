#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkMultiBlockPLOT3DReader.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkStructuredGrid.h>

#include "export_test_support.h"
#include "io/export_grid.h"
#include "io/plot3d.h"
#include "io/vtk_mesh.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

const Plot3dFormat variants[] = {
    {Plot3dEncoding::fortran, false}, {Plot3dEncoding::fortran, true},
    {Plot3dEncoding::c_binary, false}, {Plot3dEncoding::c_binary, true},
    {Plot3dEncoding::ascii, false},   {Plot3dEncoding::ascii, true},
};

std::string label(const Plot3dFormat& f) {
    const char* e = f.encoding == Plot3dEncoding::fortran ? "fortran"
                    : f.encoding == Plot3dEncoding::c_binary ? "c" : "ascii";
    return std::string(e) + (f.single_precision ? "-single" : "-double");
}

// The coordinate we expect back: the double itself, or its float rounding.
double stored(double x, bool single) { return single ? double(float(x)) : x; }

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

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCell.h>
#include <vtkCellType.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkExodusIIReader.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <Eigen/Geometry>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>

#include "export_test_support.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/exodus_mesh.h"
#include "io/fluent_mesh.h"
#include "io/gmsh_mesh.h"
#include "io/grid_faces.h"
#include "io/medit_mesh.h"
#include "io/su2_mesh.h"
#include "io/ugrid_mesh.h"
#include "io/vtk_mesh.h"
#include "volume/o_grid.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

// Same cells with the same corner coordinates (within `tolerance`), in the same order.
void expect_same_mesh(const HexMesh& got, const HexMesh& want, double tolerance = 0) {
    ASSERT_EQ(got.num_cells(), want.num_cells());
    EXPECT_EQ(got.num_points(), want.num_points());
    for (Id c = 0; c < want.num_cells(); ++c)
        for (int v = 0; v < 8; ++v)
            ASSERT_LE((got.points[got.node(c, v)] - want.points[want.node(c, v)]).norm(), tolerance)
                << c;
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
        EXPECT_TRUE(owner > previous_owner ||
                    (owner == previous_owner && neighbour > previous_neighbour));
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
        EXPECT_NE(what.find("face kmax of block 'core' is an interface (no patch), but 16 of its "
                            "16 cell faces"),
                  std::string::npos)
            << what;
        EXPECT_NE(what.find("meet no other block's: the blocks do not conform there"),
                  std::string::npos)
            << what;
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
    const ToolRun r =
        run_tool("cd '" + dir.string() + "' && gmsh grid.msh -0 -format msh41 -o again.msh");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("Error"), std::string::npos) << r.output;
    // gmsh prints 16 significant digits, so its copy is exact to ~1e-16 relative.
    expect_same_mesh(read_gmsh_mesh((dir / "again.msh").string()), to_hex_mesh(grid), 1e-14);
    const GridFaces faces = make_grid_faces(grid);
    const ToolRun info =
        run_tool("cd '" + dir.string() + "' && gmsh grid.msh -0 -o /dev/null -v 99");
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

namespace {

std::string read_text(const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// meshio's summary of a file (tests/export/meshio_summary.py), or "" when meshio is missing.
std::string meshio_summary(const fs::path& file) {
    if (run_tool("/usr/bin/python3 -c 'import meshio'").exit_code != 0) return "";
    const ToolRun r =
        run_tool("/usr/bin/python3 '" HEXMESH_SOURCE_DIR "/tests/export/meshio_summary.py' '" +
                 file.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const size_t line = r.output.rfind("\n{");  // meshio warns about string tags first
    return line == std::string::npos ? r.output : r.output.substr(line + 1);
}

// Boundary faces per patch, in GridFaces order, counted face by face (not by
// patch_face_counts, whose result the writers use).
std::vector<Id> patch_face_counts(const BlockGrid& grid) {
    const GridFaces faces = make_grid_faces(grid);
    std::vector<Id> counts(faces.patch_names.size(), 0);
    for (int p = 0; p < int(counts.size()); ++p)
        for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>&) { ++counts[p]; });
    return counts;
}

// meshio reads `file` with the grid's points, hexahedra (all right-handed) and one tag per patch
// (1, 2, ... in GridFaces order) with the patch's quads, all facing out of the domain: away from
// the sphere's centre, but into the sphere on the wall of an exterior grid.
void expect_meshio_reads(const fs::path& file, const BlockGrid& grid, bool exterior) {
    const std::string summary = meshio_summary(file);
    if (summary.empty()) GTEST_SKIP() << "python3-meshio not installed";
    const std::vector<Id> counts = patch_face_counts(grid);
    Id quads = 0;
    std::string per_tag, facing;
    for (size_t p = 0; p < counts.size(); ++p) {
        quads += counts[p];
        per_tag += fmt::format("{}\"{}\": {}", p ? ", " : "", p + 1, counts[p]);
        const bool inwards = exterior && make_grid_faces(grid).patch_names[p] == "wall";
        facing += fmt::format("{}\"{}\": {}", p ? ", " : "", p + 1, inwards ? counts[p] : 0);
    }
    EXPECT_EQ(
        summary,
        fmt::format("{{\"cells\": {{\"hexahedron\": {}, \"quad\": {}}}, \"left_handed_hexes\": 0, "
                    "\"points\": {}, \"quads_facing_origin_per_tag\": {{{}}}, \"quads_per_tag\": "
                    "{{{}}}}}\n",
                    grid.num_cells(), quads, grid.points.size(), facing, per_tag));
}

}  // namespace

TEST(Su2, MeshioReadsTheCellsPointsAndMarkers) {
    for (const bool exterior : {false, true}) {
        const BlockGrid grid = exterior ? small_o_grid() : small_o_h_grid();
        const fs::path file = scratch("su2") / "grid.su2";
        write_su2_mesh(grid, file.string());
        expect_meshio_reads(file, grid, exterior);
        // Marker names as written (meshio numbers string tags in order).
        const std::string text = read_text(file);
        const GridFaces faces = make_grid_faces(grid);
        size_t at = 0;
        for (const std::string& name : faces.patch_names) {
            at = text.find("MARKER_TAG= " + name + "\n", at);
            EXPECT_NE(at, std::string::npos) << name;
        }
        EXPECT_NE(text.find(fmt::format("NMARK= {}\n", faces.patch_names.size())),
                  std::string::npos);
    }
}

TEST(Ugrid, MeshioReadsTheCellsPointsAndSurfaceIdsAndTheMapbcNamesThem) {
    for (const bool exterior : {false, true}) {
        const BlockGrid grid = exterior ? small_o_grid() : small_o_h_grid();
        const fs::path file = scratch("ugrid") / "grid.ugrid";
        write_ugrid_mesh(grid, file.string());
        expect_meshio_reads(file, grid, exterior);
        const GridFaces faces = make_grid_faces(grid);
        std::string mapbc = fmt::format("{}\n", faces.patch_names.size());
        for (size_t p = 0; p < faces.patch_names.size(); ++p)
            mapbc += fmt::format("{} {} {}\n", p + 1, faces.patch_names[p] == "wall" ? 4000 : 5050,
                                 faces.patch_names[p]);
        EXPECT_EQ(read_text(file.parent_path() / "grid.mapbc"), mapbc);
    }
}

// meshio reads a Fluent mesh's nodes and faces (it does not build cells from faces): the
// grid's points, and every face once, interior and boundary.
TEST(Fluent, MeshioReadsThePointsAndEveryFace) {
    const BlockGrid grid = small_o_grid();
    const fs::path file = scratch("fluent") / "grid.msh";
    write_fluent_mesh(grid, file.string());
    const std::string summary = meshio_summary(file);
    if (summary.empty()) GTEST_SKIP() << "python3-meshio not installed";
    const GridFaces faces = make_grid_faces(grid);
    EXPECT_EQ(
        summary,
        fmt::format("{{\"cells\": {{\"quad\": {}}}, \"left_handed_hexes\": 0, \"points\": {}, "
                    "\"quads_facing_origin_per_tag\": {{}}, \"quads_per_tag\": {{}}}}\n",
                    faces.internal_faces + faces.boundary_faces, grid.points.size()));
}

// The exterior O-grid as Exodus II: meshio reads its points and right-handed hexahedra; VTK's
// Exodus reader (ParaView's) reads the element block "fluid" and one side set per patch, by
// name, with the patch's faces, every side facing out of the domain (into the sphere on the
// wall, away from it on the far field): the sides are numbered as Exodus numbers them.
TEST(Exodus, MeshioAndVtkReadTheBlockAndOneSideSetPerPatch) {
    const BlockGrid grid = small_o_grid();
    const fs::path file = scratch("exodus") / "grid.exo";
    write_exodus_mesh(grid, file.string());
    const std::string summary = meshio_summary(file);
    if (!summary.empty()) {
        EXPECT_EQ(
            summary,
            fmt::format(
                "{{\"cells\": {{\"hexahedron\": {}}}, \"left_handed_hexes\": 0, \"points\": {}, "
                "\"quads_facing_origin_per_tag\": {{}}, \"quads_per_tag\": {{}}}}\n",
                grid.num_cells(), grid.points.size()));
    }
    vtkNew<vtkExodusIIReader> reader;
    reader->SetFileName(file.string().c_str());
    reader->UpdateInformation();
    ASSERT_EQ(reader->GetNumberOfObjects(vtkExodusIIReader::ELEM_BLOCK), 1);
    EXPECT_STREQ(reader->GetObjectName(vtkExodusIIReader::ELEM_BLOCK, 0), "fluid");
    const GridFaces faces = make_grid_faces(grid);
    ASSERT_EQ(reader->GetNumberOfObjects(vtkExodusIIReader::SIDE_SET),
              int(faces.patch_names.size()));
    for (int s = 0; s < int(faces.patch_names.size()); ++s)
        reader->SetObjectStatus(vtkExodusIIReader::SIDE_SET, s, 1);
    reader->Update();
    const std::vector<Id> counts = patch_face_counts(grid);
    std::map<std::string, std::pair<Id, Id>> read;  // name -> (cells, cells facing the origin)
    vtkSmartPointer<vtkDataObjectTreeIterator> it =
        vtkSmartPointer<vtkDataObjectTreeIterator>::Take(
            vtkDataObjectTreeIterator::SafeDownCast(reader->GetOutput()->NewIterator()));
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
        auto* piece = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject());
        ASSERT_NE(piece, nullptr);
        const std::string name = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
        Id facing = 0;
        for (vtkIdType c = 0; c < piece->GetNumberOfCells(); ++c) {
            vtkCell* cell = piece->GetCell(c);
            if (cell->GetCellType() != VTK_QUAD) continue;
            Vec3 q[4];
            for (int m = 0; m < 4; ++m) piece->GetPoint(cell->GetPointId(m), q[m].data());
            const Vec3 normal = (q[2] - q[0]).cross(q[3] - q[1]);
            facing += normal.dot(q[0] + q[1] + q[2] + q[3]) < 0;
        }
        read[name] = {piece->GetNumberOfCells(), facing};
    }
    std::map<std::string, std::pair<Id, Id>> want = {{"fluid", {grid.num_cells(), 0}}};
    for (size_t p = 0; p < counts.size(); ++p)
        want[faces.patch_names[p]] = {counts[p], faces.patch_names[p] == "wall" ? counts[p] : 0};
    EXPECT_EQ(read, want);
}

#include <cgnslib.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCGNSReader.h>
#include <vtkCompositeDataSet.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkStructuredGrid.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "export_test_support.h"
#include "io/cgns_grid.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

#define CG(call) ASSERT_EQ((call), CG_OK) << cg_get_error()

struct Zone {
    std::string name;
    cgsize_t size[9];
    std::vector<double> xyz[3];
    Vec3 point(const cgsize_t ijk[3]) const {  // 1-based vertex index
        const Id m = (ijk[0] - 1) + size[0] * ((ijk[1] - 1) + size[1] * (ijk[2] - 1));
        return {xyz[0][m], xyz[1][m], xyz[2][m]};
    }
};

// Zone z's name, size and coordinates: those of the block of that name, bitwise.
void read_zone(int fn, int z, const BlockGrid& grid, Zone& zone, const Block*& found) {
    char name[64];
    CG(cg_zone_read(fn, 1, z, name, zone.size));
    zone.name = name;
    // The CGNS library lists zones sorted by name: find the block by its name.
    const auto block = std::find_if(grid.blocks.begin(), grid.blocks.end(),
                                    [&](const Block& b) { return b.name == zone.name; });
    ASSERT_NE(block, grid.blocks.end()) << zone.name;
    const Block& b = *block;
    found = &b;
    EXPECT_EQ(zone.size[0], b.nodes.ni);
    EXPECT_EQ(zone.size[1], b.nodes.nj);
    EXPECT_EQ(zone.size[2], b.nodes.nk);
    const cgsize_t lo[3] = {1, 1, 1}, hi[3] = {b.nodes.ni, b.nodes.nj, b.nodes.nk};
    static const char* axes[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
    for (int a = 0; a < 3; ++a) {
        zone.xyz[a].resize(b.nodes.count());
        CG(cg_coord_read(fn, 1, z, axes[a], CGNS_ENUMV(RealDouble), lo, hi, zone.xyz[a].data()));
        for (Id m = 0; m < b.nodes.count(); ++m)
            ASSERT_EQ(zone.xyz[a][m], grid.points[b.node_ids[m]][a]);  // bitwise
    }
}

// Zone z's boundary conditions: each the kmax face of block `b` as a point range, of family
// "wall"; `walls` counts them.
void check_wall_bcs(int fn, int z, const Block& b, int& walls) {
    int nbocos = 0;
    CG(cg_nbocos(fn, 1, z, &nbocos));
    for (int bc = 1; bc <= nbocos; ++bc) {
        char bc_name[64];
        CGNS_ENUMT(BCType_t) type;
        CGNS_ENUMT(PointSetType_t) set;
        cgsize_t npnts = 0, normal_size = 0;
        int normal_index[3], ndataset = 0;
        CGNS_ENUMT(DataType_t) normal_type;
        CG(cg_boco_info(fn, 1, z, bc, bc_name, &type, &set, &npnts, normal_index, &normal_size,
                        &normal_type, &ndataset));
        EXPECT_EQ(type, CGNS_ENUMV(FamilySpecified));  // the type is on the family
        EXPECT_EQ(set, CGNS_ENUMV(PointRange));
        ASSERT_EQ(npnts, 2);
        cgsize_t range[6];
        CG(cg_boco_read(fn, 1, z, bc, range, nullptr));
        // Every wall face of our O-H grid is the kmax face of its block.
        const cgsize_t want[6] = {1, 1, b.nodes.nk, b.nodes.ni, b.nodes.nj, b.nodes.nk};
        for (int m = 0; m < 6; ++m) EXPECT_EQ(range[m], want[m]) << m;
        EXPECT_EQ(b.face_patch[kmax], "wall");
        CG(cg_goto(fn, 1, "Zone_t", z, "ZoneBC_t", 1, "BC_t", bc, "end"));
        char family[64];
        CG(cg_famname_read(family));
        EXPECT_STREQ(family, "wall");
        ++walls;
    }
}

// The families carry the patches' types: one, "wall", a BCWall.
void check_families(int fn) {
    int nfamilies = 0;
    CG(cg_nfamilies(fn, 1, &nfamilies));
    std::map<std::string, CGNS_ENUMT(BCType_t)> family_type;
    for (int f = 1; f <= nfamilies; ++f) {
        char name[64];
        int nbc = 0, ngeo = 0;
        CG(cg_family_read(fn, 1, f, name, &nbc, &ngeo));
        ASSERT_EQ(nbc, 1) << name;
        char bc_name[64];
        CGNS_ENUMT(BCType_t) type;
        CG(cg_fambc_read(fn, 1, f, 1, bc_name, &type));
        family_type[name] = type;
    }
    EXPECT_EQ(family_type,
              (std::map<std::string, CGNS_ENUMT(BCType_t)>{{"wall", CGNS_ENUMV(BCWall)}}));
}

// The Transform maps every node of each of zone z's interfaces onto the same point of the donor.
void check_transforms(int fn, int z, const std::vector<Zone>& zones,
                      const std::map<std::string, int>& zone_of) {
    int n1to1 = 0;
    CG(cg_n1to1(fn, 1, z, &n1to1));
    for (int c = 1; c <= n1to1; ++c) {
        char name[64], donor[64];
        cgsize_t range[6], donor_range[6];
        int t[3];
        CG(cg_1to1_read(fn, 1, z, c, name, donor, range, donor_range, t));
        ASSERT_TRUE(zone_of.count(donor)) << donor;
        const Zone& self = zones[z - 1];
        const Zone& other = zones[zone_of.at(donor)];
        cgsize_t ijk[3];
        for (ijk[2] = range[2]; ijk[2] <= range[5]; ++ijk[2])
            for (ijk[1] = range[1]; ijk[1] <= range[4]; ++ijk[1])
                for (ijk[0] = range[0]; ijk[0] <= range[3]; ++ijk[0]) {
                    cgsize_t d[3];
                    for (int r = 0; r < 3; ++r) {
                        d[r] = donor_range[r];
                        for (int m = 0; m < 3; ++m)
                            if (std::abs(t[m]) == r + 1)
                                d[r] += (t[m] > 0 ? 1 : -1) * (ijk[m] - range[m]);
                    }
                    ASSERT_EQ(self.point(ijk), other.point(d)) << name;
                }
    }
}

}  // namespace

TEST(Cgns, LibraryReadsBackCoordinatesBcRangesAndInterfaces) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("cgns") / "grid.cgns";
    write_cgns_grid(grid, file.string());

    int fn = 0, nbases = 0, nzones = 0;
    CG(cg_open(file.string().c_str(), CG_MODE_READ, &fn));
    CG(cg_nbases(fn, &nbases));
    ASSERT_EQ(nbases, 1);
    CG(cg_nzones(fn, 1, &nzones));
    ASSERT_EQ(nzones, int(grid.blocks.size()));
    std::vector<Zone> zones(nzones);
    std::map<std::string, int> zone_of;
    int walls = 0, interfaces = 0;
    for (int z = 1; z <= nzones; ++z) {
        const Block* b = nullptr;
        ASSERT_NO_FATAL_FAILURE(read_zone(fn, z, grid, zones[z - 1], b));
        zone_of[zones[z - 1].name] = z - 1;
        ASSERT_NO_FATAL_FAILURE(check_wall_bcs(fn, z, *b, walls));
        int n1to1 = 0;
        CG(cg_n1to1(fn, 1, z, &n1to1));
        interfaces += n1to1;
    }
    ASSERT_NO_FATAL_FAILURE(check_families(fn));
    int patch_faces = 0, open_faces = 0;
    for (const Block& b : grid.blocks)
        for (const std::string& p : b.face_patch) (p.empty() ? open_faces : patch_faces) += 1;
    EXPECT_EQ(walls, patch_faces);
    EXPECT_EQ(interfaces, open_faces);  // every interface face, seen from both sides
    for (int z = 1; z <= nzones; ++z)
        ASSERT_NO_FATAL_FAILURE(check_transforms(fn, z, zones, zone_of));
    CG(cg_close(fn));
}

TEST(Cgns, CgnscheckAcceptsTheFile) {
    if (!have_tool("cgnscheck"))
        GTEST_SKIP() << "cgnscheck not installed (Debian package cgns-convert)";
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("cgnscheck") / "grid.cgns";
    write_cgns_grid(grid, file.string());
    const ToolRun r = run_tool("cgnscheck '" + file.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("ERROR"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("WARNING"), std::string::npos) << r.output;
}

// VTK's (and ParaView's) CGNS reader shows each patch by name under its zone, with the
// face's cells: it skips BC_t nodes typed BCWall or BCFarfield, but takes FamilySpecified.
TEST(Cgns, VtkReaderShowsThePatchesByName) {
    const BlockGrid grid = small_o_h_grid();
    const fs::path file = scratch("cgns_vtk") / "grid.cgns";
    write_cgns_grid(grid, file.string());
    vtkNew<vtkCGNSReader> reader;
    reader->SetFileName(file.string().c_str());
    reader->UpdateInformation();
    reader->EnableAllBases();
    reader->SetLoadBndPatch(1);
    reader->Update();
    vtkMultiBlockDataSet* base =
        vtkMultiBlockDataSet::SafeDownCast(reader->GetOutput()->GetBlock(0));
    ASSERT_NE(base, nullptr);
    ASSERT_EQ(base->GetNumberOfBlocks(), grid.blocks.size());
    std::map<std::string, Id> faces_of;  // patch name -> cells read
    std::map<std::string, Id> expected;
    for (const Block& b : grid.blocks)
        for (int f = 0; f < 6; ++f)
            if (!b.face_patch[f].empty()) {
                const Dims c = b.cells();
                const int axis = f / 2;
                expected[fmt::format("{}_{}", b.face_patch[f], block_face_names[f])] +=
                    Id(c.ni) * c.nj * c.nk / c[axis];
            }
    for (unsigned z = 0; z < base->GetNumberOfBlocks(); ++z) {
        auto* zone = vtkMultiBlockDataSet::SafeDownCast(base->GetBlock(z));
        ASSERT_NE(zone, nullptr);
        vtkMultiBlockDataSet* patches = nullptr;
        for (unsigned k = 0; k < zone->GetNumberOfBlocks(); ++k)
            if (std::string(zone->GetMetaData(k)->Get(vtkCompositeDataSet::NAME())) == "Patches")
                patches = vtkMultiBlockDataSet::SafeDownCast(zone->GetBlock(k));
        ASSERT_NE(patches, nullptr) << "zone " << z << " has no Patches";
        for (unsigned k = 0; k < patches->GetNumberOfBlocks(); ++k) {
            auto* patch = vtkStructuredGrid::SafeDownCast(patches->GetBlock(k));
            ASSERT_NE(patch, nullptr);
            faces_of[patches->GetMetaData(k)->Get(vtkCompositeDataSet::NAME())] +=
                patch->GetNumberOfCells();
        }
    }
    EXPECT_EQ(faces_of, expected);
}

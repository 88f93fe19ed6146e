#include "io/cgns_grid.h"

#include <cgnslib.h>
#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace hexmesh {
namespace {

// Zero-based node index box of one block face: lo[a] == hi[a] on its normal axis.
struct FaceBox {
    std::array<int, 3> lo, hi;
};

FaceBox face_box(const Dims& nodes, int face) {
    FaceBox box{{0, 0, 0}, {nodes.ni - 1, nodes.nj - 1, nodes.nk - 1}};
    const int axis = face / 2;
    box.lo[axis] = box.hi[axis] = face % 2 ? nodes[axis] - 1 : 0;
    return box;
}

std::set<Id> corner_ids(const Block& b, int face) {
    const FaceBox box = face_box(b.nodes, face);
    std::set<Id> ids;
    for (int c = 0; c < 8; ++c)
        ids.insert(b.node(c & 1 ? box.hi[0] : box.lo[0], c & 2 ? box.hi[1] : box.lo[1],
                          c & 4 ? box.hi[2] : box.lo[2]));
    return ids;
}

class CgnsFile {
  public:
    explicit CgnsFile(const std::string& path) : path_(path) {
        check(cg_open(path.c_str(), CG_MODE_WRITE, &fn_));
    }
    ~CgnsFile() {
        if (fn_ >= 0) cg_close(fn_);
    }
    void check(int status) const {
        if (status != CG_OK)
            throw std::runtime_error(fmt::format("{}: CGNS: {}", path_, cg_get_error()));
    }
    void close() {
        const int f = fn_;
        fn_ = -1;
        check(cg_close(f));
    }
    int fn() const { return fn_; }

  private:
    std::string path_;
    int fn_ = -1;
};

CGNS_ENUMT(BCType_t) bc_type(const std::string& patch) {
    if (patch == "wall") return CGNS_ENUMV(BCWall);
    if (patch == "farfield") return CGNS_ENUMV(BCFarfield);
    return CGNS_ENUMV(BCTypeUserDefined);
}

std::vector<std::string> zone_names(const BlockGrid& grid) {
    std::vector<std::string> names;
    std::set<std::string> seen;
    for (const Block& b : grid.blocks) {
        std::string name = b.name.substr(0, 32);
        if (name.empty() || !seen.insert(name).second) name = fmt::format("block{}", names.size());
        names.push_back(name);
    }
    return names;
}

// The GridConnectivity1to1 of face `fa` of block a onto face `fb` of block b, whose corner
// nodes are the same: 1-based ranges and the Transform (a's index axis m maps to b's axis
// |t[m]| - 1, direction sign(t[m])).
void write_1to1(const CgnsFile& file, int base, const std::vector<int>& zones,
                const std::vector<std::string>& names, const BlockGrid& grid, int a, int fa, int b,
                int fb) {
    const Block& A = grid.blocks[a];
    const Block& B = grid.blocks[b];
    const FaceBox box_a = face_box(A.nodes, fa), box_b = face_box(B.nodes, fb);
    std::unordered_map<Id, std::array<int, 3>> in_b;  // node id -> index on face fb of b
    for (int k = box_b.lo[2]; k <= box_b.hi[2]; ++k)
        for (int j = box_b.lo[1]; j <= box_b.hi[1]; ++j)
            for (int i = box_b.lo[0]; i <= box_b.hi[0]; ++i)
                in_b.emplace(B.node(i, j, k), std::array<int, 3>{i, j, k});
    auto donor = [&](const std::array<int, 3>& ijk) {
        const auto it = in_b.find(A.node(ijk[0], ijk[1], ijk[2]));
        if (it == in_b.end())
            throw std::runtime_error(
                fmt::format("blocks '{}' and '{}': interface nodes do not match", A.name, B.name));
        return it->second;
    };
    const std::array<int, 3> begin_b = donor(box_a.lo), end_b = donor(box_a.hi);
    int transform[3];
    const int na = fa / 2, nb = fb / 2;
    for (int m = 0; m < 3; ++m) {
        if (m == na) {
            // Leaving a through its face enters b: a's outward step is b's inward one.
            const int sa = fa % 2 ? 1 : -1, sb = fb % 2 ? 1 : -1;
            transform[m] = -sa * sb * (nb + 1);
            continue;
        }
        std::array<int, 3> step = box_a.lo;
        step[m] += 1;
        const std::array<int, 3> d = donor(step);
        transform[m] = 0;
        for (int n = 0; n < 3; ++n)
            if (d[n] != begin_b[n]) transform[m] = (d[n] > begin_b[n] ? 1 : -1) * (n + 1);
    }
    cgsize_t range[6], donor_range[6];
    for (int m = 0; m < 3; ++m) {
        range[m] = box_a.lo[m] + 1;
        range[m + 3] = box_a.hi[m] + 1;
        donor_range[m] = begin_b[m] + 1;
        donor_range[m + 3] = end_b[m] + 1;
    }
    int index = 0;
    const std::string name =
        fmt::format("{}_{}_to_{}", names[a], block_face_names[fa], names[b]).substr(0, 32);
    file.check(cg_1to1_write(file.fn(), base, zones[a], name.c_str(), names[b].c_str(), range,
                             donor_range, transform, &index));
}

}  // namespace

void write_cgns_grid(const BlockGrid& grid, const std::string& path) {
    CgnsFile file(path);
    int base = 0;
    file.check(cg_base_write(file.fn(), "Base", 3, 3, &base));
    // Coordinates are in the user's geometry units, which we do not know.
    file.check(cg_goto(file.fn(), base, "end"));
    file.check(cg_dataclass_write(CGNS_ENUMV(NormalizedByUnknownDimensional)));

    std::vector<std::string> families;
    for (const Block& b : grid.blocks)
        for (const std::string& patch : b.face_patch)
            if (!patch.empty() &&
                std::find(families.begin(), families.end(), patch) == families.end())
                families.push_back(patch);
    for (const std::string& family : families) {
        int f = 0, fbc = 0;
        file.check(cg_family_write(file.fn(), base, family.c_str(), &f));
        file.check(cg_fambc_write(file.fn(), base, f, "FamBC", bc_type(family), &fbc));
    }

    const std::vector<std::string> names = zone_names(grid);
    std::vector<int> zones(grid.blocks.size());
    std::vector<double> coord;
    for (size_t z = 0; z < grid.blocks.size(); ++z) {
        const Block& b = grid.blocks[z];
        const Dims c = b.cells();
        const cgsize_t size[9] = {b.nodes.ni, b.nodes.nj, b.nodes.nk, c.ni, c.nj, c.nk, 0, 0, 0};
        file.check(cg_zone_write(file.fn(), base, names[z].c_str(), size, CGNS_ENUMV(Structured),
                                 &zones[z]));
        static const char* axes[3] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
        coord.resize(b.nodes.count());
        for (int a = 0; a < 3; ++a) {
            for (Id m = 0; m < b.nodes.count(); ++m) coord[m] = grid.points[b.node_ids[m]][a];
            int index = 0;
            file.check(cg_coord_write(file.fn(), base, zones[z], CGNS_ENUMV(RealDouble), axes[a],
                                      coord.data(), &index));
            // A length: exponents of mass, length, time, temperature, angle.
            const float length[5] = {0, 1, 0, 0, 0};
            file.check(cg_goto(file.fn(), base, "Zone_t", zones[z], "GridCoordinates_t", 1,
                               "DataArray_t", index, "end"));
            file.check(cg_exponents_write(CGNS_ENUMV(RealSingle), length));
        }
        for (int f = 0; f < 6; ++f) {
            const std::string& patch = b.face_patch[f];
            if (patch.empty()) continue;
            const FaceBox box = face_box(b.nodes, f);
            const cgsize_t range[6] = {box.lo[0] + 1, box.lo[1] + 1, box.lo[2] + 1,
                                       box.hi[0] + 1, box.hi[1] + 1, box.hi[2] + 1};
            int bc = 0;
            const std::string name = fmt::format("{}_{}", patch, block_face_names[f]).substr(0, 32);
            // The type lives on the patch's family (FamilyBC_t): readers that take only some BC
            // types on a BC_t (VTK's, ParaView's) take FamilySpecified with the family's name.
            file.check(cg_boco_write(file.fn(), base, zones[z], name.c_str(),
                                     CGNS_ENUMV(FamilySpecified), CGNS_ENUMV(PointRange), 2, range,
                                     &bc));
            file.check(
                cg_goto(file.fn(), base, "Zone_t", zones[z], "ZoneBC_t", 1, "BC_t", bc, "end"));
            file.check(cg_famname_write(patch.c_str()));
        }
    }

    // Interfaces: block faces without a patch whose corners coincide with another such face.
    std::vector<std::array<std::set<Id>, 6>> corners(grid.blocks.size());
    for (size_t z = 0; z < grid.blocks.size(); ++z)
        for (int f = 0; f < 6; ++f)
            if (grid.blocks[z].face_patch[f].empty()) corners[z][f] = corner_ids(grid.blocks[z], f);
    for (size_t a = 0; a < grid.blocks.size(); ++a)
        for (int fa = 0; fa < 6; ++fa) {
            if (corners[a][fa].empty()) continue;
            for (size_t b = 0; b < grid.blocks.size(); ++b)
                for (int fb = 0; fb < 6; ++fb)
                    if ((a != b || fa != fb) && corners[b][fb] == corners[a][fa])
                        write_1to1(file, base, zones, names, grid, int(a), fa, int(b), fb);
        }
    file.close();
}

}  // namespace hexmesh

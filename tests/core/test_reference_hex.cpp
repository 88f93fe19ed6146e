// The reference hexahedron tables: corner tets, faces and edges on the unit cube.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <set>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/cell_quality.h"

namespace hexmesh {
namespace {

std::array<Vec3, 8> unit_cube() {
    std::array<Vec3, 8> p;
    for (int c = 0; c < 8; ++c) {
        const int x = (c == 1 || c == 2 || c == 5 || c == 6);
        const int y = (c == 2 || c == 3 || c == 6 || c == 7);
        p[c] = Vec3(x, y, c >= 4);
    }
    return p;
}

TEST(ReferenceHex, NodeOrderIsVtkOnUnitCube) {
    const auto p = unit_cube();
    EXPECT_EQ(p[0], Vec3(0, 0, 0));
    EXPECT_EQ(p[2], Vec3(1, 1, 0));
    EXPECT_EQ(p[5], Vec3(1, 0, 1));
    EXPECT_EQ(p[7], Vec3(0, 1, 1));
}

TEST(ReferenceHex, CornerDeterminantsAreOneOnUnitCube) {
    for (double det : corner_determinants(unit_cube())) EXPECT_EQ(det, 1.0);
}

TEST(ReferenceHex, CornerDeterminantsScaleWithTheBox) {
    auto p = unit_cube();
    for (Vec3& q : p) q = Vec3(2 * q[0], 3 * q[1], 0.5 * q[2]) + Vec3(7, -1, 4);
    for (double det : corner_determinants(p)) EXPECT_DOUBLE_EQ(det, 3.0);
}

TEST(ReferenceHex, EachCornerTetIsACornerAndItsThreeEdgeNeighbours) {
    std::array<std::set<int>, 8> neighbours;
    for (const auto& [a, b] : hex_edges) {
        neighbours[a].insert(b);
        neighbours[b].insert(a);
    }
    std::set<int> corners;
    for (const auto& [c, a, b, d] : hex_corner_tets) {
        corners.insert(c);
        EXPECT_EQ(neighbours[c].size(), 3u);
        EXPECT_EQ((std::set<int>{a, b, d}), neighbours[c]) << "corner " << c;
    }
    EXPECT_EQ(corners.size(), 8u);  // every corner has its own tet
    for (int t = 0; t < 8; ++t) EXPECT_EQ(hex_corner_tets[t][0], t);
}

TEST(ReferenceHex, FacesPointOutward) {
    const auto p = unit_cube();
    const Vec3 centre(0.5, 0.5, 0.5);
    for (const auto& f : hex_faces) {
        const Vec3 fc = 0.25 * (p[f[0]] + p[f[1]] + p[f[2]] + p[f[3]]);
        // Area vector of a quad: half the cross product of its diagonals.
        const Vec3 area = 0.5 * (p[f[2]] - p[f[0]]).cross(p[f[3]] - p[f[1]]);
        EXPECT_DOUBLE_EQ(area.norm(), 1.0);
        EXPECT_GT(area.dot(fc - centre), 0.0);
        EXPECT_DOUBLE_EQ(area.normalized().dot((fc - centre).normalized()), 1.0);
    }
}

TEST(ReferenceHex, EveryEdgeIsInExactlyTwoFaces) {
    std::map<std::pair<int, int>, int> uses;
    for (const auto& f : hex_faces)
        for (int i = 0; i < 4; ++i) {
            const int a = f[i], b = f[(i + 1) % 4];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    EXPECT_EQ(uses.size(), 12u);  // face sides are exactly the 12 edges
    for (const auto& [a, b] : hex_edges) EXPECT_EQ((uses[{std::min(a, b), std::max(a, b)}]), 2);
    EXPECT_EQ(uses.size(), 12u);
}

TEST(ReferenceHex, EdgesAreGroupedByDirection) {
    const auto p = unit_cube();
    for (int e = 0; e < 12; ++e) {
        const Vec3 d = p[hex_edges[e][1]] - p[hex_edges[e][0]];
        EXPECT_EQ(d, Vec3::Unit(e / 4)) << "edge " << e;
    }
}

}  // namespace
}  // namespace hexmesh

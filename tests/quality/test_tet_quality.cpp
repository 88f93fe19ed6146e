// Tests of the tet quality metrics: dihedral angles, radius ratio, slivers and inversions,
// against closed forms, face normals and VTK's Verdict (radius ratio) on random tets.
// (Verdict's TetMinAngle is not used: it skips some edges and reports a larger angle.)
#include <gtest/gtest.h>
#include <vtkMeshQuality.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkTetra.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "hexmesh/quality/tet_quality.h"

namespace hexmesh {
namespace {

const double regular_dihedral = std::acos(1.0 / 3.0) * 180 / std::acos(-1.0);  // 70.5288 degrees

std::array<Vec3, 4> regular_tet() {
    return {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
}

// The dihedral angles from the outward face normals: pi minus the angle between the normals
// of the two faces at each edge (an independent way to the same numbers).
std::vector<double> dihedrals_from_normals(const std::array<Vec3, 4>& p) {
    const Vec3 centre = 0.25 * (p[0] + p[1] + p[2] + p[3]);
    auto outward = [&](int opposite) {
        std::array<Vec3, 3> f;
        for (int i = 0, k = 0; i < 4; ++i)
            if (i != opposite) f[k++] = p[i];
        Vec3 n = (f[1] - f[0]).cross(f[2] - f[0]).normalized();
        return n.dot(f[0] - centre) < 0 ? Vec3(-n) : n;
    };
    std::vector<double> angles;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
            int others[2], k = 0;
            for (int i = 0; i < 4; ++i)
                if (i != a && i != b) others[k++] = i;
            const double c = std::clamp(outward(others[0]).dot(outward(others[1])), -1.0, 1.0);
            angles.push_back(180 - std::acos(c) * 180 / std::acos(-1.0));
        }
    return angles;
}

double vtk_radius_ratio(const std::array<Vec3, 4>& p) {  // Verdict: R / (3 r), 1 for regular
    vtkNew<vtkTetra> tet;
    for (int i = 0; i < 4; ++i) {
        tet->GetPointIds()->SetId(i, i);
        tet->GetPoints()->SetPoint(i, p[i][0], p[i][1], p[i][2]);
    }
    return vtkMeshQuality::TetRadiusRatio(tet);
}

TEST(TetQuality, RegularTetHasEqualAnglesAndRatioOne) {
    auto p = regular_tet();
    if ((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) < 0) std::swap(p[2], p[3]);
    for (double a : dihedral_angles(p)) EXPECT_NEAR(a, regular_dihedral, 1e-12);
    EXPECT_NEAR(radius_ratio(p), 1.0, 1e-12);
}

TEST(TetQuality, RightCornerTetAngles) {
    // The corner of the unit cube: three 90 degree dihedrals at the corner's edges, and
    // arccos(1/sqrt(3)) = 54.74 degrees at the edges of the slanted face.
    const std::array<Vec3, 4> p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const auto a = dihedral_angles(p);
    const double slanted = std::acos(1 / std::sqrt(3.0)) * 180 / std::acos(-1.0);
    EXPECT_NEAR(a[0], 90, 1e-12);  // edge 01
    EXPECT_NEAR(a[1], 90, 1e-12);  // edge 02
    EXPECT_NEAR(a[2], 90, 1e-12);  // edge 03
    for (int e = 3; e < 6; ++e) EXPECT_NEAR(a[e], slanted, 1e-12);
    // r = 1 / (3 + sqrt 3), R = sqrt(3) / 2.
    EXPECT_NEAR(radius_ratio(p), 3 * (1 / (3 + std::sqrt(3.0))) / (std::sqrt(3.0) / 2), 1e-12);
}

TEST(TetQuality, FlatAndInvertedTetsScoreZero) {
    const std::array<Vec3, 4> flat = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
    const auto a = dihedral_angles(flat);
    EXPECT_NEAR(*std::min_element(a.begin(), a.end()), 0, 1e-12);
    EXPECT_EQ(radius_ratio(flat), 0);
    std::array<int, 4> order = {0, 1, 2, 3};  // every order of its points: 0, never 180
    do {
        EXPECT_EQ(smallest_dihedral_angle(
                      {flat[order[0]], flat[order[1]], flat[order[2]], flat[order[3]]}),
                  0);
    } while (std::next_permutation(order.begin(), order.end()));
    std::array<Vec3, 4> inverted = regular_tet();
    if ((inverted[1] - inverted[0])
            .dot((inverted[2] - inverted[0]).cross(inverted[3] - inverted[0])) > 0)
        std::swap(inverted[2], inverted[3]);
    EXPECT_EQ(radius_ratio(inverted), 0);
    EXPECT_NEAR(smallest_dihedral_angle(inverted), std::acos(1.0 / 3) * 180 / std::acos(-1.0),
                1e-9);  // the mirror image's
}

TEST(TetQuality, AgreesWithNormalsAndVerdictOnRandomTets) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coordinate(-1, 1);
    for (int t = 0; t < 500; ++t) {
        std::array<Vec3, 4> p;
        for (Vec3& q : p) q = Vec3(coordinate(rng), coordinate(rng), coordinate(rng));
        if ((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) < 0) std::swap(p[2], p[3]);
        const auto a = dihedral_angles(p);
        const auto reference = dihedrals_from_normals(p);
        for (int e = 0; e < 6; ++e) EXPECT_NEAR(a[e], reference[e], 1e-7);
        EXPECT_NEAR(radius_ratio(p), 1 / vtk_radius_ratio(p), 1e-9);
        EXPECT_NEAR(smallest_dihedral_angle(p), *std::min_element(a.begin(), a.end()), 1e-7);
        std::swap(p[0], p[1]);  // inverted: the same angles
        EXPECT_NEAR(smallest_dihedral_angle(p), *std::min_element(a.begin(), a.end()), 1e-7);
    }
}

TEST(TetQuality, MeshReportCountsSliversAndInversions) {
    TetMesh mesh;
    mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0),    Vec3(0, 1, 0),
                   Vec3(0, 0, 1), Vec3(1, 1, 0.05), Vec3(0, 0, -1)};
    mesh.tets = {
        0, 1,
        2, 3,  // right corner: fine
        0, 1,
        2, 4,  // four corners of a square, one lifted: a sliver (dihedral well below 10 degrees)
        0, 2,
        1, 3};  // the first one inverted
    const TetQualityReport r = measure_tet_quality(mesh);
    EXPECT_EQ(r.cells, 3);
    EXPECT_EQ(r.points, 6);
    EXPECT_EQ(r.inverted, 1);
    EXPECT_GE(r.slivers, 1);
    EXPECT_GT(r.max_dihedral, 90);
    EXPECT_LT(r.min_dihedral, 10);
    EXPECT_EQ(r.min_radius_ratio, 0);  // the inverted one
}

}  // namespace
}  // namespace hexmesh

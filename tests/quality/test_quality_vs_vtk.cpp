// hex_scaled_jacobian against VTK's vtkMeshQuality::HexScaledJacobian (Verdict), the reference.
#include <gtest/gtest.h>
#include <vtkHexahedron.h>
#include <vtkMeshQuality.h>
#include <vtkNew.h>
#include <vtkPoints.h>

#include <cmath>
#include <random>

#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/validity.h"

namespace hexmesh {
namespace {

double vtk_scaled_jacobian(const std::array<Vec3, 8>& p) {
    vtkNew<vtkHexahedron> hex;
    for (int i = 0; i < 8; ++i) {
        hex->GetPointIds()->SetId(i, i);
        hex->GetPoints()->SetPoint(i, p[i][0], p[i][1], p[i][2]);
    }
    return vtkMeshQuality::HexScaledJacobian(hex);
}

std::array<Vec3, 8> unit_cube() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
            Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

void expect_agree(const std::array<Vec3, 8>& p, int& bitwise_equal) {
    const double ours = hex_scaled_jacobian(p), vtk = vtk_scaled_jacobian(p);
    EXPECT_LE(std::abs(ours - vtk), 1e-12 * std::abs(vtk)) << "ours " << ours << " vtk " << vtk;
    bitwise_equal += ours == vtk;
}

TEST(ScaledJacobianVsVtk, RandomPerturbedHexes) {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> noise(-0.45, 0.45), scale(0.01, 100.0);
    std::uniform_real_distribution<double> shift(-1e3, 1e3);
    int inverted = 0, bitwise_equal = 0;
    const int n = 1000;
    for (int t = 0; t < n; ++t) {
        // Every 5th hex gets a node moved far enough to fold it.
        const double amplitude = t % 5 == 0 ? 1.6 : 1.0;
        const double s = scale(rng);
        const Vec3 o(shift(rng), shift(rng), shift(rng));
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& q : p) q = o + s * (q + amplitude * Vec3(noise(rng), noise(rng), noise(rng)));
        inverted += hex_scaled_jacobian(p) < 0;
        expect_agree(p, bitwise_equal);
    }
    EXPECT_GT(inverted, 20);  // the sample does contain folded hexes
    EXPECT_LT(inverted, n / 2);
    // Same operations in the same order: VTK's numbers are reproduced to the last bit.
    EXPECT_EQ(bitwise_equal, n);
}

TEST(ScaledJacobianVsVtk, ShearedHexesMatchClosedForm) {
    int bitwise_equal = 0;
    for (double s : {0.0, 0.1, 0.5, 1.0, 3.0, 10.0, -2.0}) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& q : p) q[0] += s * q[1];  // x += s y: parallelepiped
        expect_agree(p, bitwise_equal);
        EXPECT_NEAR(hex_scaled_jacobian(p), 1 / std::sqrt(1 + s * s), 1e-15);
    }
    for (double s : {0.2, 0.7}) {  // shear in two directions at once
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& q : p) q += Vec3(s * q[2], 0, s * q[0]);
        expect_agree(p, bitwise_equal);
    }
    EXPECT_EQ(bitwise_equal, 9);
}

TEST(ScaledJacobianVsVtk, DegenerateEdgeGivesVerdictMax) {
    std::array<Vec3, 8> p = unit_cube();
    p[6] = p[5];  // a zero-length edge: Verdict returns its DBL_MAX, 1e30
    EXPECT_EQ(vtk_scaled_jacobian(p), 1e30);
    EXPECT_EQ(hex_scaled_jacobian(p), 1e30);
    EXPECT_GE(count_inverted_corner_tets(p), 1);  // the validity count still flags it

    std::array<Vec3, 8> flat = unit_cube();
    for (Vec3& q : flat) q[2] = 0;  // flat hex: zero-length vertical edges
    EXPECT_EQ(hex_scaled_jacobian(flat), vtk_scaled_jacobian(flat));

    std::array<Vec3, 8> tiny = unit_cube();
    for (Vec3& q : tiny) q *= 1e-16;  // squared lengths 1e-32 < Verdict's 1e-30
    EXPECT_EQ(hex_scaled_jacobian(tiny), vtk_scaled_jacobian(tiny));
    EXPECT_EQ(hex_scaled_jacobian(tiny), 1e30);
}

TEST(ScaledJacobianVsVtk, MirroredCubeIsMinusOne) {
    std::array<Vec3, 8> p = unit_cube();
    for (Vec3& q : p) q[2] = -q[2];  // every corner frame is left-handed
    EXPECT_EQ(hex_scaled_jacobian(p), -1.0);
    EXPECT_EQ(vtk_scaled_jacobian(p), -1.0);
}

}  // namespace
}  // namespace hexmesh

// Sharp creases of a triangle surface seen through its signed distance field: the pieces of
// MeshSdf::active_pieces drive the same classification, crease projection and corner snapping
// as an analytic box or cylinder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "surface/implicit_features.h"
#include "surface/mesh_sdf.h"
#include "tests/surface/sample_surfaces.h"

namespace hexmesh {
namespace {

const Vec3 lo(-1, -0.5, -0.7), hi(1, 0.5, 0.7);

MeshSdf box_sdf(bool reversed, double feature_angle = 30) {
    TriangleSurface box = test::box_surface(lo, hi, 4);
    if (reversed)
        for (auto& t : box.triangles) std::swap(t[1], t[2]);
    MeshSdfOptions o;
    o.voxel_size = 0.02;
    o.feature_angle = feature_angle;
    return MeshSdf(box, o);
}

// Distance from p to the nearest of the box's 12 edges.
double edge_distance(const Vec3& p) {
    double best = INFINITY;
    for (int a = 0; a < 3; ++a)
        for (int sb : {0, 1})
            for (int sc : {0, 1}) {
                const int b = (a + 1) % 3, c = (a + 2) % 3;
                Vec3 q;
                q[a] = std::clamp(p[a], lo[a], hi[a]);
                q[b] = sb ? hi[b] : lo[b];
                q[c] = sc ? hi[c] : lo[c];
                best = std::min(best, (p - q).norm());
            }
    return best;
}

class BoxStlCreases : public ::testing::TestWithParam<bool> {};

TEST_P(BoxStlCreases, ClassifiesFacesEdgesAndCornersLikeTheAnalyticBox) {
    const MeshSdf sdf = box_sdf(GetParam());
    EXPECT_EQ(sdf.creases().crease_edges(), 12 * 4);
    EXPECT_EQ(sdf.creases().corners(), 8);
    const double t = 1e-6;
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.1, 0.2), t), FeatureKind::smooth);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.5, 0.2), t), FeatureKind::crease);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0.3, -0.5, -0.7), t), FeatureKind::crease);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.5, 0.7), t), FeatureKind::corner);
    // Within the tolerance of an edge, as for the analytic box; beyond it smooth.
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.45, 0.2), 0.06), FeatureKind::crease);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.45, 0.2), 0.04), FeatureKind::smooth);
    // The pieces are the faces' planes, negative inside whatever the file's orientation.
    std::vector<ImplicitFunction::Piece> pieces;
    sdf.active_pieces(Vec3(0.99, 0.49, 0.2), 0.05, pieces);
    ASSERT_EQ(pieces.size(), 2u);
    for (const auto& p : pieces) {
        EXPECT_NEAR(p.value, -0.01, 1e-12);
        EXPECT_NEAR(p.gradient.norm(), 1, 1e-12);
    }
    const Vec3 tangent = crease_tangent(sdf, Vec3(1, 0.5, 0.2), 1e-6);
    EXPECT_NEAR(std::abs(tangent.z()), 1, 1e-12);
}

TEST_P(BoxStlCreases, ProjectsOntoEdgesAndSnapsToCorners) {
    const MeshSdf sdf = box_sdf(GetParam());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> along(-0.6, 0.6), off(-0.08, 0.08);
    for (int i = 0; i < 50; ++i) {
        // Near the edge x = 1, y = 0.5, on or off the surface.
        const Vec3 p(1 + off(rng), 0.5 + off(rng), along(rng));
        const Vec3 q = project_to_crease(sdf, p, 0.1);
        EXPECT_LT(edge_distance(q), 1e-9) << p.transpose() << " -> " << q.transpose();
        EXPECT_NEAR(q.z(), p.z(), 0.1);
        // A projected point stays put.
        EXPECT_LT((project_to_crease(sdf, q, 0.1) - q).norm(), 1e-9);
    }
    const Vec3 corner = snap_to_corner(sdf, Vec3(-0.95, 0.46, 0.72), 0.1);
    EXPECT_LT((corner - Vec3(-1, 0.5, 0.7)).norm(), 1e-9) << corner.transpose();
}

INSTANTIATE_TEST_SUITE_P(Orientation, BoxStlCreases, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Reversed" : "Outward"; });

// A tent: a prism of length 4 whose cross-section is the triangle (-1, 0), (1, 0), (0, 0.4)
// in (y, z). Its ridge (a 44-degree crease) passes 0.4 above the middle of the bottom face;
// there, with a tolerance that reaches the ridge, the ridge's planes are about -0.37, far
// from the body's value 0: the bottom stays smooth, the ridge is a crease.
TEST(MeshCreases, ACreaseElsewhereDoesNotMakeAFaceSharp) {
    TriangleSurface tent;
    for (double x : {-2.0, 2.0})
        for (const Vec3& q : {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(0, 0, 0.4)})
            tent.points.push_back(Vec3(x, q.y(), q.z()));
    // Points: 0..2 at x = -2 (left foot, right foot, apex), 3..5 at x = 2.
    tent.triangles = {{0, 2, 1}, {3, 4, 5},   // end caps
                      {0, 1, 4}, {0, 4, 3},   // bottom
                      {1, 2, 5}, {1, 5, 4},   // roof y > 0
                      {0, 3, 5}, {0, 5, 2}};  // roof y < 0
    MeshSdfOptions o;
    o.voxel_size = 0.02;
    const MeshSdf sdf(tent, o);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0, 0, 0), 0.25), FeatureKind::smooth);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0, 0, 0.4), 1e-6), FeatureKind::crease);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0, 0.95, 0.02), 0.06), FeatureKind::crease);
}

TEST(MeshCreases, AngleOf180MeansASmoothBody) {
    const MeshSdf sdf = box_sdf(false, 180);
    EXPECT_EQ(sdf.creases().crease_edges(), 0);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.5, 0.2), 0.05), FeatureKind::smooth);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(1, 0.5, 0.7), 0.05), FeatureKind::smooth);
}

// The rims of a 64-sided cylinder are creases everywhere along them, never corners (their
// side facets turn by 5.6 degrees), and projection lands on a rim segment.
TEST(MeshCreases, CylinderRimsAreCreasesAllAround) {
    const int segments = 64;
    const double r = 0.6;
    MeshSdfOptions o;
    o.voxel_size = 0.01;
    const MeshSdf sdf(test::cylinder_surface(r, 1.4, segments), o);
    EXPECT_EQ(sdf.creases().crease_edges(), 2 * segments);
    EXPECT_EQ(sdf.creases().corners(), 0);
    const double inner = r * std::cos(3.14159265358979 / segments);  // the chords' distance
    for (int i = 0; i < 200; ++i) {
        const double phi = 0.0314 * i, z = i % 2 ? 0.7 : -0.7;
        const Vec3 on(r * std::cos(phi), r * std::sin(phi), z);
        EXPECT_EQ(classify_surface_point(sdf, on, 0.02), FeatureKind::crease) << i;
        const Vec3 near =
            on + Vec3(0.02 * std::cos(phi), 0.02 * std::sin(phi), z > 0 ? -0.03 : 0.03);
        const Vec3 q = project_to_crease(sdf, near, 0.05);
        EXPECT_NEAR(q.z(), z, 1e-9) << i;
        EXPECT_GE(q.head<2>().norm(), inner - 1e-9) << i;
        EXPECT_LE(q.head<2>().norm(), r + 1e-9) << i;
    }
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0, 0.5, 0.7), 0.02), FeatureKind::smooth);
    EXPECT_EQ(classify_surface_point(sdf, Vec3(0.6, 0, 0), 0.02), FeatureKind::smooth);
}

}  // namespace
}  // namespace hexmesh

// Sharp features of triangle surfaces: creases by dihedral angle, corners, projection.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "surface/sharp_features.h"
#include "tests/surface/sample_surfaces.h"
#include "tests/surface/test_helpers.h"

namespace hexmesh {
namespace {

// Number of box axes along which p sits on the lower or upper face of [0, size].
int faces_touching(const Vec3& p, const Vec3& size) {
    int n = 0;
    for (int a = 0; a < 3; ++a) n += std::abs(p[a]) < 1e-12 || std::abs(p[a] - size[a]) < 1e-12;
    return n;
}

TEST(SharpFeatures, BoxHasTwelveEdgesAndEightCorners) {
    const Vec3 size(2, 1, 3);
    for (int n : {1, 4}) {
        const TriangleSurface box = test::box_surface(Vec3::Zero(), size, n);
        const FeatureCurves f = detect_sharp_features(box);
        EXPECT_EQ(f.chains.size(), 12u) << "n = " << n;
        EXPECT_EQ(f.corners.size(), 8u) << "n = " << n;
        for (int c : f.corners) EXPECT_EQ(faces_touching(box.points[c], size), 3);
        for (const auto& chain : f.chains) {
            EXPECT_EQ(chain.size(), size_t(n + 1));  // corner to corner, n segments
            EXPECT_NE(chain.front(), chain.back());
            for (int p : chain) EXPECT_GE(faces_touching(box.points[p], size), 2);
        }
    }
}

TEST(SharpFeatures, ThresholdAboveTheBoxAngleFindsNothing) {
    FeatureOptions o;
    o.angle_degrees = 95;
    const FeatureCurves f =
        detect_sharp_features(test::box_surface(Vec3::Zero(), Vec3::Ones(), 2), o);
    EXPECT_TRUE(f.chains.empty());
    EXPECT_TRUE(f.corners.empty());
}

TEST(SharpFeatures, CylinderHasTwoCircularCreases) {
    const int segments = 48;  // neighbouring side facets turn by 7.5 degrees
    const TriangleSurface cylinder = test::cylinder_surface(1.0, 2.0, segments);
    const FeatureCurves f = detect_sharp_features(cylinder);
    EXPECT_TRUE(f.corners.empty());
    ASSERT_EQ(f.chains.size(), 2u);
    for (const auto& chain : f.chains) {
        EXPECT_EQ(chain.size(), size_t(segments + 1));
        EXPECT_EQ(chain.front(), chain.back());  // closed loop
        const double z = cylinder.points[chain[0]].z();
        EXPECT_NEAR(std::abs(z), 1.0, 1e-12);
        for (int p : chain) {
            EXPECT_EQ(cylinder.points[p].z(), z);
            EXPECT_NEAR(cylinder.points[p].head<2>().norm(), 1.0, 1e-12);
        }
    }
}

TEST(SharpFeatures, SmoothSphereHasNoCrease) {
    const FeatureCurves f = detect_sharp_features(test::uv_sphere(Vec3::Zero(), 1, 32, 16));
    EXPECT_TRUE(f.chains.empty());
    EXPECT_TRUE(f.corners.empty());
}

TEST(SharpFeatures, FacetsOfAScanAreNoiseNotCreases) {
    const TriangleSurface scan = test::bumpy_sphere();
    FeatureOptions o;  // 30 degrees
    const FeatureCurves all = detect_sharp_features(scan, o);
    ASSERT_GT(all.turning_edges, 0);
    EXPECT_FALSE(all.chains.empty());  // many short "creases" at 30 degrees
    // ... but at least half as many edges beside them turn by 15-30 degrees: no gap between the
    // facets and the creases.
    EXPECT_GE(2 * all.half_turning_edges, all.turning_edges);
    o.noise_ratio = 0.5;
    const FeatureCurves noise = detect_sharp_features(scan, o);
    EXPECT_TRUE(noise.noise);
    EXPECT_TRUE(noise.chains.empty());
    EXPECT_TRUE(noise.corners.empty());
    EXPECT_EQ(noise.turning_edges, all.turning_edges);

    // A box has no edge between flat and 90 degrees: its creases stay, subdivided or not.
    for (int n : {1, 4}) {
        const FeatureCurves box =
            detect_sharp_features(test::box_surface(Vec3::Zero(), Vec3(2, 1, 3), n), o);
        EXPECT_FALSE(box.noise);
        EXPECT_EQ(box.half_turning_edges, 0);
        EXPECT_EQ(box.chains.size(), 12u);
        EXPECT_EQ(box.corners.size(), 8u);
    }
    o.noise_ratio = -1;
    EXPECT_THROW(detect_sharp_features(scan, o), std::invalid_argument);
}

TEST(SharpFeatures, OpenSheetRimIsAFeatureUnlessExcluded) {
    TriangleSurface sheet;
    sheet.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
    const FeatureCurves f = detect_sharp_features(sheet);
    ASSERT_EQ(f.chains.size(), 1u);
    EXPECT_EQ(f.chains[0].size(), 5u);  // the closed rim of 4 edges
    FeatureOptions o;
    o.include_boundary = false;
    EXPECT_TRUE(detect_sharp_features(sheet, o).chains.empty());
}

TEST(SharpFeatures, ProjectionLandsAndStaysOnTheCrease) {
    const Vec3 size(2, 1, 3);
    const TriangleSurface box = test::box_surface(Vec3::Zero(), size, 3);
    const FeatureCurves f = detect_sharp_features(box);
    std::mt19937 rng(5);
    for (int n = 0; n < 200; ++n) {
        const Vec3 p = test::random_in_box(rng, Vec3::Constant(-0.5), size + Vec3::Constant(0.5));
        const FeatureProjection q = project_to_features(box, f, p);
        ASSERT_GE(q.chain, 0);
        EXPECT_GE(faces_touching(q.point, size), 2);  // on one of the 12 edges
        // No point of any edge is closer: compare with the exact distance to the 12 edges.
        double exact = 1e9;
        for (int a = 0; a < 3; ++a)
            for (double u : {0.0, size[(a + 1) % 3]})
                for (double v : {0.0, size[(a + 2) % 3]}) {
                    Vec3 e;
                    e[a] = std::clamp(p[a], 0.0, size[a]);
                    e[(a + 1) % 3] = u;
                    e[(a + 2) % 3] = v;
                    exact = std::min(exact, (p - e).norm());
                }
        EXPECT_NEAR(q.distance, exact, 1e-12);
        const FeatureProjection again = project_to_features(box, f, q.point);
        EXPECT_LT((again.point - q.point).norm(), 1e-12);
        EXPECT_LT(again.distance, 1e-12);
    }
}

// The indexed projection gives the brute force's nearest point, and its segment holds it.
TEST(SharpFeatures, IndexedProjectionIsTheBruteForceOne) {
    const Vec3 size(2, 1, 3);
    const TriangleSurface box = test::box_surface(Vec3::Zero(), size, 3);
    const FeatureCurves f = detect_sharp_features(box);
    const FeatureIndex index(box, f);
    ASSERT_FALSE(index.empty());
    std::mt19937 rng(8);
    for (int n = 0; n < 500; ++n) {
        const Vec3 p = test::random_in_box(rng, Vec3::Constant(-0.5), size + Vec3::Constant(0.5));
        const FeatureProjection brute = project_to_features(box, f, p);
        const FeatureProjection fast = index.project(p);
        EXPECT_NEAR(fast.distance, brute.distance, 1e-12);
        ASSERT_GE(fast.chain, 0);
        const Vec3& a = box.points[f.chains[fast.chain][fast.segment]];
        const Vec3& b = box.points[f.chains[fast.chain][fast.segment + 1]];
        EXPECT_NEAR((fast.point - a).norm() + (b - fast.point).norm(), (b - a).norm(), 1e-12);
    }
    EXPECT_TRUE(FeatureIndex(box, FeatureCurves{}).empty());
    EXPECT_EQ(FeatureIndex(box, FeatureCurves{}).project(Vec3(1, 2, 3)).chain, -1);
}

}  // namespace
}  // namespace hexmesh

// Point-cloud implicit function against the exact distance to a sampled unit sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "surface/point_cloud.h"
#include "tests/surface/test_helpers.h"

namespace hexmesh {
namespace {

// n points on the sphere (Fibonacci lattice, spacing ~ sqrt(4 pi / n) r) with outward normals.
OrientedPoints sphere_cloud(int n, double radius, const Vec3& center = Vec3::Zero()) {
    OrientedPoints cloud;
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
        const Vec3 normal(r * std::cos(golden * i), r * std::sin(golden * i), z);
        cloud.points.push_back(center + radius * normal);
        cloud.normals.push_back(3 * normal);  // not unit: normalized by PointCloudSdf
    }
    return cloud;
}

// Radius where u changes sign along the ray from the centre in `direction` (bisection).
double zero_crossing(const ImplicitFunction& u, const Vec3& direction) {
    double inside = 0.5, outside = 1.5;
    for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (inside + outside);
        (u.value(mid * direction) < 0 ? inside : outside) = mid;
    }
    return 0.5 * (inside + outside);
}

class SphereCloud : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { sdf_ = new PointCloudSdf(sphere_cloud(4000, 1.0)); }
    static void TearDownTestSuite() { delete sdf_; }
    static inline PointCloudSdf* sdf_ = nullptr;
};

TEST_F(SphereCloud, SpacingAndBoundsFollowThePoints) {
    EXPECT_GT(sdf_->mean_spacing(), 0.03);
    EXPECT_LT(sdf_->mean_spacing(), 0.06);
    EXPECT_EQ(sdf_->bandwidth(), sdf_->mean_spacing());
    const Box3 b = sdf_->bounds();
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(b.lo[a], -1.0);
        EXPECT_GT(b.hi[a], 1.0);
        EXPECT_LT(b.hi[a], 1.3);
    }
}

TEST_F(SphereCloud, IsTheSignedDistanceNearTheSurface) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> radius(0.8, 1.2);
    double worst = 0;
    for (int k = 0; k < 2000; ++k) {
        const Vec3 p = radius(rng) * test::random_unit_vector(rng);
        worst = std::max(worst, std::abs(sdf_->value(p) - (p.norm() - 1)));
    }
    EXPECT_LT(worst, 0.02);
    std::printf("max |u - (|x| - 1)| for |x| in [0.8, 1.2]: %.2e\n", worst);
}

TEST_F(SphereCloud, SignIsRightAtTheCentreAndFarAway) {
    EXPECT_NEAR(sdf_->value(Vec3::Zero()), -1.0, 0.02);
    EXPECT_LT(sdf_->value(Vec3(0.1, -0.2, 0.3)), -0.5);
    std::mt19937 rng(4);
    for (int k = 0; k < 50; ++k) {
        const Vec3 p = 10 * test::random_unit_vector(rng);
        EXPECT_NEAR(sdf_->value(p), 9.0, 0.1) << p.transpose();
    }
}

TEST_F(SphereCloud, ZeroLevelIsAtRadiusOne) {
    std::mt19937 rng(5);
    double worst = 0;
    for (int k = 0; k < 200; ++k)
        worst = std::max(worst, std::abs(zero_crossing(*sdf_, test::random_unit_vector(rng)) - 1));
    EXPECT_LT(worst, 0.01);
    std::printf("max |r(u = 0) - 1| along 200 rays: %.2e\n", worst);
}

// The gradient jumps a little (~3e-3) where the (k+1)-th neighbour changes; a central
// difference straddles such a kink at a few of the samples.
TEST_F(SphereCloud, GradientIsTheDerivativeOfTheValueAndAboutUnit) {
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> radius(0.9, 1.1);
    int off = 0;
    for (int k = 0; k < 200; ++k) {
        const Vec3 p = radius(rng) * test::random_unit_vector(rng);
        const Vec3 g = sdf_->gradient(p);
        const double error = (g - test::central_difference(*sdf_, p, 1e-6)).norm();
        off += error > 1e-4;
        EXPECT_LT(error, 2e-2) << p.transpose();
        EXPECT_NEAR(g.norm(), 1.0, 0.1) << p.transpose();
        EXPECT_GT(g.dot(p.normalized()), 0.95) << p.transpose();
    }
    EXPECT_LE(off, 4);
}

TEST_F(SphereCloud, ConcurrentQueriesAgreeWithSerialOnes) {
    std::vector<Vec3> points;
    std::mt19937 rng(7);
    for (int k = 0; k < 4000; ++k)
        points.push_back(test::random_in_box(rng, Vec3(-2, -2, -2), Vec3(2, 2, 2)));
    std::vector<double> serial(points.size()), parallel(points.size());
    for (size_t k = 0; k < points.size(); ++k) serial[k] = sdf_->value(points[k]);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (size_t k = t; k < points.size(); k += 4) parallel[k] = sdf_->value(points[k]);
        });
    for (auto& thread : threads) thread.join();
    EXPECT_EQ(serial, parallel);
}

TEST(PointCloudSdf, FollowsAShiftedScaledSphere) {
    const Vec3 c(10, -5, 2);
    const PointCloudSdf sdf(sphere_cloud(3000, 50.0, c));  // units kept: spacing ~1.6
    EXPECT_NEAR(sdf.value(c + Vec3(55, 0, 0)), 5.0, 0.5);
    EXPECT_NEAR(sdf.value(c + Vec3(0, 0, -45)), -5.0, 0.5);
    EXPECT_NEAR(sdf.value(c), -50.0, 1.0);
}

TEST(PointCloudSdf, RefusesBadInput) {
    EXPECT_THROW(PointCloudSdf(OrientedPoints{}), std::invalid_argument);
    OrientedPoints cloud = sphere_cloud(10, 1.0);
    cloud.normals.pop_back();
    EXPECT_THROW(PointCloudSdf{cloud}, std::invalid_argument);
    cloud = sphere_cloud(10, 1.0);
    cloud.normals[3] = Vec3::Zero();
    EXPECT_THROW(PointCloudSdf{cloud}, std::invalid_argument);
    PointCloudSdfOptions options;
    options.neighbours = 0;
    EXPECT_THROW(PointCloudSdf(sphere_cloud(10, 1.0), options), std::invalid_argument);
}

TEST(PointCloudSdf, FewerPointsThanNeighboursStillWork) {
    const PointCloudSdf sdf(sphere_cloud(6, 1.0));
    EXPECT_LT(sdf.value(Vec3::Zero()), 0);
    EXPECT_GT(sdf.value(Vec3(3, 0, 0)), 0);
}

}  // namespace
}  // namespace hexmesh

// Tests of Transformed and rotation_from_axis_angle.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "surface/analytic.h"
#include "surface/transform.h"
#include "test_helpers.h"

namespace hexmesh {
namespace {

using test::random_in_box;

TEST(RotationFromAxisAngle, QuarterTurnAboutZ) {
    const Mat3 r = rotation_from_axis_angle(Vec3(0, 0, 2), 90);
    EXPECT_LT((r * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-15);
    EXPECT_LT((r * Vec3::UnitZ() - Vec3::UnitZ()).norm(), 1e-15);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
    EXPECT_THROW(rotation_from_axis_angle(Vec3::Zero(), 10), std::invalid_argument);
}

TEST(Transformed, MovedSphereIsTheSphereWithMovedCentreAndRadius) {
    const Vec3 c(0.2, -0.1, 0.4), t(1.0, 2.0, -0.5);
    const Mat3 r = rotation_from_axis_angle(Vec3(1, 2, 3), 37);
    const double s = 2.5;
    const Transformed moved(std::make_shared<Sphere>(c, 0.7), t, r, s);
    const Sphere expected(t + s * r * c, s * 0.7);
    std::mt19937 rng(11);
    const Box3 b = expected.bounds();
    for (int i = 0; i < 500; ++i) {
        const Vec3 p = random_in_box(rng, b.lo - b.size(), b.hi + b.size());
        EXPECT_NEAR(moved.value(p), expected.value(p), 1e-13);
        EXPECT_LT((moved.gradient(p) - expected.gradient(p)).norm(), 1e-13);
    }
    EXPECT_LT((moved.bounds().center() - expected.bounds().center()).norm(), 1e-13);
}

TEST(Transformed, GradientIsTheRotatedChildGradient) {
    const auto box = std::make_shared<Box>(Vec3(0.1, 0.2, 0.3), Vec3(1.0, 0.5, 0.25));
    const Vec3 t(-0.3, 0.4, 1.0);
    const Mat3 r = rotation_from_axis_angle(Vec3(-1, 1, 0.5), 63);
    const double s = 0.8;
    const Transformed moved(box, t, r, s);
    std::mt19937 rng(12);
    const Box3 b = moved.bounds();
    int checked = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p = random_in_box(rng, b.lo - 0.3 * b.size(), b.hi + 0.3 * b.size());
        const Vec3 y = r.transpose() * (p - t) / s;
        EXPECT_NEAR(moved.value(p), s * box->value(y), 1e-14);
        EXPECT_LT((moved.gradient(p) - r * box->gradient(y)).norm(), 1e-14);
        if (!test::smooth_near(moved, p)) continue;
        ++checked;
        EXPECT_LT((moved.gradient(p) - test::central_difference(moved, p)).norm(), 1e-6);
        EXPECT_NEAR(moved.gradient(p).norm(), 1.0, 1e-12);
    }
    EXPECT_GT(checked, 700);
}

TEST(Transformed, BoundsOfARotatedBox) {
    const auto box = std::make_shared<Box>(Vec3::Zero(), Vec3(1.0, 0.5, 0.25));
    const Transformed moved(box, Vec3(1, 1, 1), rotation_from_axis_angle(Vec3::UnitZ(), 45), 2);
    const double half = 2 * (1.0 + 0.5) / std::sqrt(2.0);
    EXPECT_LT((moved.bounds().lo - Vec3(1 - half, 1 - half, 0.5)).norm(), 1e-14);
    EXPECT_LT((moved.bounds().hi - Vec3(1 + half, 1 + half, 1.5)).norm(), 1e-14);
}

TEST(Transformed, RejectsBadArguments) {
    const auto sphere = std::make_shared<Sphere>(Vec3::Zero(), 1.0);
    EXPECT_THROW(Transformed(sphere, Vec3::Zero(), Mat3::Identity(), 0.0), std::invalid_argument);
    EXPECT_THROW(Transformed(sphere, Vec3::Zero(), 2 * Mat3::Identity()), std::invalid_argument);
    EXPECT_THROW(Transformed(nullptr, Vec3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace hexmesh

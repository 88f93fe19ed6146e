// Tests of CSG bodies: values, active child and its gradient, bounds.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "surface/analytic.h"
#include "surface/csg.h"
#include "test_helpers.h"

namespace hexmesh {
namespace {

// Box [-1,1] x [-0.5,0.5]^2 and a sphere of radius 0.5 centred on its +x face.
const auto box = std::make_shared<Box>(Vec3::Zero(), Vec3(1.0, 0.5, 0.5));
const auto ball = std::make_shared<Sphere>(Vec3(1, 0, 0), 0.5);

TEST(Csg, UnionIsTheNearerBody) {
    const Csg u(CsgOp::Union, {box, ball});
    EXPECT_NEAR(u.value(Vec3(1.3, 0, 0)), -0.2, 1e-15);  // in the ball, outside the box
    EXPECT_EQ(u.active_child(Vec3(1.3, 0, 0)), 1);
    EXPECT_NEAR(u.value(Vec3(-0.8, 0, 0)), -0.2, 1e-15);  // in the box only
    EXPECT_EQ(u.active_child(Vec3(-0.8, 0, 0)), 0);
    EXPECT_NEAR(u.value(Vec3(-2, 0, 0)), 1.0, 1e-15);
    EXPECT_NEAR(u.value(Vec3(2, 0, 0)), 0.5, 1e-15);
    const Vec3 p(1.6, 0.3, 0.1);
    EXPECT_EQ(u.gradient(p), ball->gradient(p));
    EXPECT_LT(u.value(Vec3(1.4, 0, 0)), 0);
}

TEST(Csg, IntersectionIsTheFartherBody) {
    const Csg u(CsgOp::Intersection, {box, ball});
    EXPECT_NEAR(u.value(Vec3(0.9, 0, 0)), -0.1, 1e-15);  // box face is nearer than sphere
    EXPECT_NEAR(u.value(Vec3(1.3, 0, 0)), 0.3, 1e-15);   // outside the box
    EXPECT_EQ(u.active_child(Vec3(1.3, 0, 0)), 0);
    EXPECT_NEAR(u.value(Vec3(0.0, 0, 0)), 0.5, 1e-15);  // outside the ball
    EXPECT_EQ(u.gradient(Vec3(0.0, 0.1, 0)), ball->gradient(Vec3(0.0, 0.1, 0)));
    EXPECT_LT((u.bounds().lo - Vec3(0.5, -0.5, -0.5)).norm(), 1e-15);
    EXPECT_LT((u.bounds().hi - Vec3(1.0, 0.5, 0.5)).norm(), 1e-15);
}

TEST(Csg, DifferenceCarvesTheSecondBodyOut) {
    const Csg u(CsgOp::Difference, {box, ball});
    EXPECT_NEAR(u.value(Vec3(0.9, 0, 0)), 0.4, 1e-15);  // in the hole
    EXPECT_EQ(u.active_child(Vec3(0.9, 0, 0)), 1);
    EXPECT_EQ(u.gradient(Vec3(0.9, 0.05, 0)), Vec3(-ball->gradient(Vec3(0.9, 0.05, 0))));
    EXPECT_NEAR(u.value(Vec3(-0.8, 0, 0)), -0.2, 1e-15);  // solid part, box face nearest
    EXPECT_EQ(u.gradient(Vec3(-0.8, 0, 0)), Vec3(-1, 0, 0));
    EXPECT_NEAR(u.value(Vec3(2, 0, 0)), 1.0, 1e-15);
    EXPECT_LT((u.bounds().lo - box->bounds().lo).norm(), 1e-15);
    EXPECT_LT((u.bounds().hi - box->bounds().hi).norm(), 1e-15);
}

TEST(Csg, SeveralSubtractedBodies) {
    const auto ball2 = std::make_shared<Sphere>(Vec3(-1, 0, 0), 0.25);
    const Csg u(CsgOp::Difference, {box, ball, ball2});
    EXPECT_NEAR(u.value(Vec3(-0.9, 0, 0)), 0.15, 1e-15);
    EXPECT_EQ(u.active_child(Vec3(-0.9, 0, 0)), 2);
    EXPECT_EQ(u.gradient(Vec3(-0.9, 0, 0)), Vec3(-1, 0, 0));
}

TEST(Csg, UnionBoundsAndGradientMatchFiniteDifferences) {
    const Csg u(CsgOp::Union, {box, ball});
    EXPECT_LT((u.bounds().lo - Vec3(-1, -0.5, -0.5)).norm(), 1e-15);
    EXPECT_LT((u.bounds().hi - Vec3(1.5, 0.5, 0.5)).norm(), 1e-15);
    std::mt19937 rng(13);
    int checked = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p = test::random_in_box(rng, Vec3(-2, -1, -1), Vec3(2.5, 1, 1));
        if (!test::smooth_near(u, p)) continue;
        ++checked;
        EXPECT_LT((u.gradient(p) - test::central_difference(u, p)).norm(), 1e-6);
    }
    EXPECT_GT(checked, 700);
}

TEST(Csg, RejectsMissingChildren) {
    EXPECT_THROW(Csg(CsgOp::Union, {}), std::invalid_argument);
    EXPECT_THROW(Csg(CsgOp::Union, {box, nullptr}), std::invalid_argument);
}

}  // namespace
}  // namespace hexmesh

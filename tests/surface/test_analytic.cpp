// Tests of the analytic primitives: known values, exact distances, gradients, bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "surface/analytic.h"
#include "test_helpers.h"

namespace hexmesh {
namespace {

using test::central_difference;
using test::random_in_box;
using test::smooth_near;

const Vec3 c0(0.3, -0.2, 0.7);  // an off-origin centre for every body

// Checks gradient() against central differences of value() at random points of the
// (enlarged) bounds away from kinks; for exact SDFs also |grad u| = 1. Returns the number
// of points checked.
int check_gradient(const ImplicitFunction& u, bool exact_distance, unsigned seed) {
    std::mt19937 rng(seed);
    const Box3 b = u.bounds();
    const Vec3 margin = 0.5 * b.size();
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = random_in_box(rng, b.lo - margin, b.hi + margin);
        if (!smooth_near(u, p)) continue;
        ++checked;
        const Vec3 g = u.gradient(p);
        const Vec3 fd = central_difference(u, p);
        EXPECT_LT((g - fd).norm(), 1e-6 * g.norm()) << "at " << p.transpose();
        if (exact_distance) {
            EXPECT_NEAR(g.norm(), 1.0, 1e-12) << "at " << p.transpose();
        }
    }
    EXPECT_GT(checked, 1500) << "too few points away from kinks: the filter is wrong";
    return checked;
}

void expect_bounds(const ImplicitFunction& u, const Vec3& lo, const Vec3& hi) {
    EXPECT_LT((u.bounds().lo - lo).norm(), 1e-14);
    EXPECT_LT((u.bounds().hi - hi).norm(), 1e-14);
}

TEST(Sphere, ValuesAreSignedDistances) {
    const Sphere s(c0, 0.8);
    EXPECT_DOUBLE_EQ(s.value(c0), -0.8);
    EXPECT_NEAR(s.value(c0 + Vec3(0, 0.8, 0)), 0.0, 1e-15);
    EXPECT_NEAR(s.value(c0 + Vec3(0.6, 0, 0.8) * 2.0), 2.0 - 0.8, 1e-15);
    EXPECT_NEAR(s.value(c0 + Vec3(0.3, 0, 0)), -0.5, 1e-15);
}

TEST(Sphere, GradientAndBounds) {
    const Sphere s(c0, 0.8);
    check_gradient(s, true, 1);
    expect_bounds(s, c0 - Vec3::Constant(0.8), c0 + Vec3::Constant(0.8));
    EXPECT_DOUBLE_EQ(s.gradient(c0).norm(), 1.0);  // a unit vector even at the centre
    EXPECT_THROW(Sphere(c0, 0.0), std::invalid_argument);
}

TEST(Ellipsoid, ValuesAlongAxesAreExactDistances) {
    const Vec3 a(1.0, 0.5, 0.25);
    const Ellipsoid e(c0, a);
    EXPECT_DOUBLE_EQ(e.value(c0), -0.25);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(e.value(c0 + a[k] * Vec3::Unit(k)), 0.0, 1e-15);
        EXPECT_NEAR(e.value(c0 + (a[k] + 0.3) * Vec3::Unit(k)), 0.3, 1e-14);
        EXPECT_NEAR(e.value(c0 - (a[k] - 0.1) * Vec3::Unit(k)), -0.1, 1e-14);
    }
}

TEST(Ellipsoid, SurfaceSignAndUnitGradientOnTheSurface) {
    const Vec3 a(1.0, 0.5, 0.25);
    const Ellipsoid e(c0, a);
    std::mt19937 rng(2);
    for (int i = 0; i < 500; ++i) {
        const Vec3 on = c0 + test::random_unit_vector(rng).cwiseProduct(a);
        EXPECT_NEAR(e.value(on), 0.0, 1e-14);
        EXPECT_NEAR(central_difference(e, on).norm(), 1.0, 1e-6);
        EXPECT_LT(e.value(c0 + 0.9 * (on - c0)), 0.0);
        EXPECT_GT(e.value(c0 + 1.1 * (on - c0)), 0.0);
    }
    expect_bounds(e, c0 - a, c0 + a);
}

TEST(Box, ValuesInsideOnFacesAndNearCorners) {
    const Vec3 h(1.0, 0.6, 0.4);
    const Box b(c0, h);
    EXPECT_DOUBLE_EQ(b.value(c0), -0.4);
    EXPECT_NEAR(b.value(c0 + Vec3(1.0, 0.1, -0.2)), 0.0, 1e-15);
    EXPECT_NEAR(b.value(c0 + Vec3(-1.5, 0.1, 0.0)), 0.5, 1e-15);
    EXPECT_NEAR(b.value(c0 + Vec3(0.9, 0.0, 0.0)), -0.1, 1e-15);
    EXPECT_NEAR(b.value(c0 + h + Vec3(0.1, 0.2, 0.2)), 0.3, 1e-15);  // past a corner
    EXPECT_NEAR(b.value(c0 + Vec3(1.3, -1.0, 0.0)), 0.5, 1e-15);     // past an edge
}

TEST(Box, GradientAndBounds) {
    const Vec3 h(1.0, 0.6, 0.4);
    const Box b(c0, h);
    check_gradient(b, true, 3);
    expect_bounds(b, c0 - h, c0 + h);
    EXPECT_EQ(b.gradient(c0 + Vec3(0.2, 0.1, -0.3)), Vec3(0, 0, -1));  // nearest face -z
}

TEST(Cylinder, Values) {
    const Cylinder c(c0, 0.5, 1.0);
    EXPECT_DOUBLE_EQ(c.value(c0), -0.5);
    EXPECT_NEAR(c.value(c0 + Vec3(0.3, 0.4, 0.2)), 0.0, 1e-15);
    EXPECT_NEAR(c.value(c0 + Vec3(0.0, 0.0, -1.25)), 0.25, 1e-15);
    EXPECT_NEAR(c.value(c0 + Vec3(0.0, 0.3, 0.9)), -0.1, 1e-15);
    EXPECT_NEAR(c.value(c0 + Vec3(0.6, 0.8, 1.4)), std::hypot(0.5, 0.4), 1e-15);  // rim
}

TEST(Cylinder, GradientAndBounds) {
    const Cylinder c(c0, 0.5, 1.0);
    check_gradient(c, true, 4);
    expect_bounds(c, c0 - Vec3(0.5, 0.5, 1.0), c0 + Vec3(0.5, 0.5, 1.0));
}

TEST(Torus, Values) {
    const Torus t(c0, 1.0, 0.25);
    EXPECT_DOUBLE_EQ(t.value(c0), 0.75);                              // hole centre
    EXPECT_NEAR(t.value(c0 + Vec3(0, -1.0, 0)), -0.25, 1e-15);        // core circle
    EXPECT_NEAR(t.value(c0 + Vec3(0.6, 0.8, 0) * 1.5), 0.25, 1e-15);  // outside
    EXPECT_NEAR(t.value(c0 + Vec3(0.8, 0.6, 0.25)), 0.0, 1e-15);      // top
    EXPECT_NEAR(t.value(c0 + Vec3(0, 0, 0.5)), std::hypot(1.0, 0.5) - 0.25, 1e-15);
}

TEST(Torus, GradientAndBounds) {
    const Torus t(c0, 1.0, 0.25);
    check_gradient(t, true, 5);
    expect_bounds(t, c0 - Vec3(1.25, 1.25, 0.25), c0 + Vec3(1.25, 1.25, 0.25));
    EXPECT_THROW(Torus(c0, 0.2, 0.3), std::invalid_argument);
}

TEST(Cone, ValuesOfAPointedCone) {
    const Cone k(c0, 1.0, 0.0, 1.0);          // base radius 1 at z = -1, apex at z = +1
    const double slant = 1 / std::sqrt(5.0);  // distance from the axis centre to the slant
    EXPECT_NEAR(k.value(c0), -slant, 1e-15);
    EXPECT_NEAR(k.value(c0 + Vec3(0, 0, 2)), 1.0, 1e-15);          // above the apex
    EXPECT_NEAR(k.value(c0 + Vec3(2, 0, -1)), 1.0, 1e-15);         // past the base rim
    EXPECT_NEAR(k.value(c0 + Vec3(0, 1.5, 0)), 2 * slant, 1e-15);  // off the slant
    EXPECT_NEAR(k.value(c0 + Vec3(0.3, 0.4, -3)), 2.0, 1e-15);     // below the base
    EXPECT_NEAR(k.value(c0 + Vec3(0, 0.5, 0)), 0.0, 1e-15);        // on the slant
    EXPECT_NEAR(k.value(c0 + Vec3(0, 0, -0.9)), -0.1, 1e-15);      // just above the base
}

// A frustum with equal radii is the cylinder: an independent check of the meridian code.
TEST(Cone, EqualRadiiGiveTheCylinder) {
    const Cone k(c0, 0.5, 0.5, 1.0);
    const Cylinder c(c0, 0.5, 1.0);
    std::mt19937 rng(6);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = random_in_box(rng, c0 - Vec3::Constant(2), c0 + Vec3::Constant(2));
        EXPECT_NEAR(k.value(p), c.value(p), 1e-14) << p.transpose();
    }
}

// Distance by brute force: the nearest of many samples of the meridian outline.
TEST(Cone, FrustumMatchesBruteForceDistance) {
    const double r0 = 0.4, r1 = 0.9, h = 0.6;
    const Cone k(c0, r0, r1, h);
    std::vector<Eigen::Vector2d> outline;
    const int n = 20000;
    for (int i = 0; i <= n; ++i) {
        const double s = double(i) / n;
        outline.emplace_back(s * r0, -h);
        outline.emplace_back(r0 + s * (r1 - r0), -h + 2 * h * s);
        outline.emplace_back(s * r1, h);
    }
    std::mt19937 rng(7);
    for (int i = 0; i < 300; ++i) {
        const Vec3 p = random_in_box(rng, c0 - Vec3(1.5, 1.5, 1.2), c0 + Vec3(1.5, 1.5, 1.2));
        const Vec3 d = p - c0;
        const Eigen::Vector2d q(std::hypot(d.x(), d.y()), d.z());
        double dist = std::numeric_limits<double>::infinity();
        for (const auto& o : outline) dist = std::min(dist, (q - o).norm());
        const bool inside = std::abs(q.y()) < h && q.x() < r0 + (r1 - r0) * (q.y() + h) / (2 * h);
        EXPECT_NEAR(k.value(p), inside ? -dist : dist, 1e-4) << p.transpose();
    }
}

TEST(Cone, GradientAndBounds) {
    const Cone pointed(c0, 1.0, 0.0, 1.0);
    const Cone frustum(c0, 0.4, 0.9, 0.6);
    check_gradient(pointed, true, 8);
    check_gradient(frustum, true, 9);
    expect_bounds(frustum, c0 - Vec3(0.9, 0.9, 0.6), c0 + Vec3(0.9, 0.9, 0.6));
    EXPECT_THROW(Cone(c0, 0.0, 0.0, 1.0), std::invalid_argument);
}

// Exact signed distances are 1-Lipschitz and the nearest surface point sits at p - u grad u.
TEST(Analytic, ExactDistancesHaveTheirNearestPointOnTheSurface) {
    const std::vector<std::shared_ptr<ImplicitFunction>> bodies = {
        std::make_shared<Sphere>(c0, 0.8),         std::make_shared<Box>(c0, Vec3(1.0, 0.6, 0.4)),
        std::make_shared<Cylinder>(c0, 0.5, 1.0),  std::make_shared<Torus>(c0, 1.0, 0.25),
        std::make_shared<Cone>(c0, 1.0, 0.0, 1.0), std::make_shared<Cone>(c0, 0.4, 0.9, 0.6)};
    std::mt19937 rng(10);
    for (const auto& u : bodies) {
        const Box3 b = u->bounds();
        for (int i = 0; i < 500; ++i) {
            const Vec3 p = random_in_box(rng, b.lo - 0.3 * b.size(), b.hi + 0.3 * b.size());
            const Vec3 q = random_in_box(rng, b.lo - 0.3 * b.size(), b.hi + 0.3 * b.size());
            EXPECT_LE(std::abs(u->value(p) - u->value(q)), (p - q).norm() + 1e-14);
            const double f = u->value(p);
            EXPECT_NEAR(u->value(p - f * u->gradient(p)), 0.0, 1e-12) << p.transpose();
        }
    }
}

}  // namespace
}  // namespace hexmesh

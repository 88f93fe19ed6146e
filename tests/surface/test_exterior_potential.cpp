#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "surface/analytic.h"
#include "surface/csg.h"
#include "surface/exterior_potential.h"
#include "surface/level_sets.h"

using namespace hexmesh;

TEST(ExteriorPotential, VanishesOnTheBodyAndRisesToOneAtTheBox) {
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 48;
    const ExteriorPotential f(body, o);
    EXPECT_GT(f.unknowns(), 0);
    for (const Vec3& d : sphere_directions(50)) {
        // On the body, between lattice nodes: the zero level within a quarter of a node spacing.
        EXPECT_LT(std::abs(f.value(0.5 * d)) / f.gradient(0.5 * d).norm(), 0.25 * f.spacing());
        EXPECT_LT(f.value(0.4 * d), 0);  // inside
        // Along the ray out of the body: strictly increasing up to the box (no maximum inside).
        double previous = f.value(0.5 * d);
        for (double r = 0.52; r < 0.5 + 0.11; r += 0.02) {
            const double v = f.value(r * d);
            EXPECT_GT(v, previous);
            EXPECT_LT(v, 1);
            previous = v;
        }
    }
    EXPECT_NEAR(f.value(f.bounds().hi), 1, 1e-12);
    EXPECT_GT(f.value(f.bounds().hi + Vec3::Ones()), 1);  // beyond the box: 1 + the distance
}

TEST(ExteriorPotential, ItsLevelsAroundASphereAreSpheresNearTheBody) {
    // Near a small sphere in a large box the potential is the capacitor's, a function of the
    // radius alone: its level at 0.05 lies at one radius whatever the direction.
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 32;
    o.margin = 0.6;
    const ExteriorPotential f(body, o);
    double lo = 1e9, hi = 0;
    for (const Vec3& d : sphere_directions(200)) {
        double a = 0.5, b = 1.4;  // bisection for f = 0.05 on the ray
        for (int it = 0; it < 60; ++it) {
            const double m = 0.5 * (a + b);
            (f.value(m * d) < 0.05 ? a : b) = m;
        }
        lo = std::min(lo, a), hi = std::max(hi, a);
    }
    EXPECT_GT(lo, 0.5);
    EXPECT_LT(hi - lo, 0.02 * lo);
}

TEST(ExteriorPotential, EntersAGapFromItsOpeningAndItsLevelsAreStarShapedFarOut) {
    // A U: two bars joined at the bottom. Inside the gap the potential is lower deep down than
    // at the opening, and its high levels are star-shaped around the centre though the body
    // is not.
    const Body left = std::make_shared<Box>(Vec3(-0.4, 0, 0), Vec3(0.1, 0.5, 0.2));
    const Body right = std::make_shared<Box>(Vec3(0.4, 0, 0), Vec3(0.1, 0.5, 0.2));
    const Body bottom = std::make_shared<Box>(Vec3(0, -0.4, 0), Vec3(0.5, 0.1, 0.2));
    const Csg u(CsgOp::Union, {left, right, bottom});
    ExteriorPotentialOptions o;
    o.resolution = 40;
    const ExteriorPotential f(u, o);
    EXPECT_LT(f.value(Vec3(0, -0.2, 0)), f.value(Vec3(0, 0.2, 0)));
    EXPECT_LT(f.value(Vec3(0, 0.2, 0)), f.value(Vec3(0, 0.6, 0)));
    const std::vector<Vec3> rays = sphere_directions(500);
    const double step = f.spacing() / 2, reach = 2;
    EXPECT_FALSE(star_shaped_level(u, 0, Vec3(0, -0.4, 0), rays, step, reach, 90));
    std::vector<Vec3> crossings;
    EXPECT_TRUE(star_shaped_level(f, 0.9, Vec3::Zero(), rays, step, reach, 80, &crossings));
    // Where each ray crosses the level: on it, to the sampling's linear interpolation.
    ASSERT_EQ(crossings.size(), rays.size());
    for (size_t r = 0; r < rays.size(); ++r) EXPECT_NEAR(f.value(crossings[r]), 0.9, 0.01) << r;
}

TEST(ExteriorPotential, InsideItFallsFromOneOnTheSourceBallToZeroOnTheWall) {
    // A ball of radius 0.1 at the centre of a sphere of radius 0.5: the potential is the
    // spherical capacitor's, a function of the radius alone, decreasing outwards; outside the
    // body it is negative.
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 48;
    o.source_radius = 0.1;
    const ExteriorPotential f(body, o);
    EXPECT_GT(f.unknowns(), 0);
    const auto capacitor = [](double r) { return (1 / r - 1 / 0.5) / (1 / 0.1 - 1 / 0.5); };
    for (const Vec3& d : sphere_directions(50)) {
        // The zero level within a third of a node spacing of the wall.
        EXPECT_LT(std::abs(f.value(0.5 * d)) / f.gradient(0.5 * d).norm(), f.spacing() / 3);
        EXPECT_LT(f.value(0.55 * d), 0);  // outside
        EXPECT_NEAR(f.value(0.05 * d), 1, 1e-12);
        double previous = f.value(0.12 * d);
        for (double r = 0.14; r < 0.49; r += 0.02) {
            const double v = f.value(r * d);
            EXPECT_LT(v, previous);
            EXPECT_GT(v, 0);
            EXPECT_NEAR(v, capacitor(r), 0.02);
            previous = v;
        }
    }
    EXPECT_LT(f.value(f.bounds().hi + Vec3::Ones()), 0);  // beyond the lattice: still outside
}

TEST(ExteriorPotential, ASourceBallWithNoNodeInsideTheBodyIsRefused) {
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 16;
    o.source_centre = Vec3(2, 0, 0);
    o.source_radius = 0.1;
    EXPECT_THROW(ExteriorPotential(body, o), std::invalid_argument);
}

TEST(HarmonicDirections, RoundASphereWithRadialDataTheyAreRadial) {
    // Radial on the sphere and on the box: by symmetry radial in between (up to the box's
    // corners), of length at most 1 (the maximum principle, component by component).
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 32;
    o.margin = 0.6;
    const HarmonicDirections theta(
        body, [](const Vec3& x) { return Vec3(x.normalized()); }, Vec3::Zero(), o);
    EXPECT_GT(theta.iterations(), 0);
    for (const Vec3& d : sphere_directions(100))
        for (double r = 0.55; r < 1.0; r += 0.1) {
            const Vec3 t = theta.value(r * d);
            EXPECT_LT(std::acos(std::min(1.0, t.normalized().dot(d))), 2 * M_PI / 180)
                << "at " << (r * d).transpose();
            EXPECT_LT(t.norm(), 1 + 1e-6);
        }
    EXPECT_NEAR(theta.value(Vec3(5, 0, 0)).x(), 1, 1e-12);  // beyond the box: radial
}

// Bars of one thickness are as deep all along their axes: of the points as deep as the
// deepest, the first candidate is where the bars meet (its ball of twice the depth holds the
// most of the body), the others at least the depth apart.
TEST(DeepestPoint, BarsOfOneThicknessMeetAtTheFirstCandidate) {
    const Body ell = std::make_shared<Csg>(
        CsgOp::Union,
        std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(0.5, 0.15, 0.15)),
                          std::make_shared<Box>(Vec3(-0.35, 0.35, 0), Vec3(0.15, 0.5, 0.15))});
    const Body cross = std::make_shared<Csg>(
        CsgOp::Union,
        std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(0.5, 0.1, 0.1)),
                          std::make_shared<Box>(Vec3(0.15, 0, 0), Vec3(0.1, 0.5, 0.1))});
    for (const auto& [body, meet, half] :
         {std::tuple{ell, Vec3(-0.35, 0, 0), 0.15}, std::tuple{cross, Vec3(0.15, 0, 0), 0.1}}) {
        const double step = body->bounds().diagonal() / 60;
        const std::vector<Vec3> c = deepest_candidates(depth_lattice(*body, step), 8);
        ASSERT_EQ(c.size(), 8u);
        // Within the square where the bars meet, and as deep as the deepest to half the step.
        EXPECT_LT((c[0] - meet).head<2>().cwiseAbs().maxCoeff(), half) << c[0].transpose();
        for (const Vec3& x : c) EXPECT_NEAR(-body->value(x), half, 0.5 * step) << x.transpose();
        for (size_t i = 0; i < c.size(); ++i)
            for (size_t j = 0; j < i; ++j) EXPECT_GE((c[i] - c[j]).norm(), 0.9 * half);
    }
}

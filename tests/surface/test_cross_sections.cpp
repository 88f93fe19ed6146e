// Cross-section stacks: a cylinder and a cone frustum against their exact distances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "surface/cross_sections.h"
#include "tests/surface/test_helpers.h"

namespace hexmesh {
namespace {

using Vec2 = Eigen::Vector2d;

std::vector<Vec2> circle(double radius, int n = 512) {
    std::vector<Vec2> loop;
    for (int i = 0; i < n; ++i)
        loop.emplace_back(radius * std::cos(2 * M_PI * i / n), radius * std::sin(2 * M_PI * i / n));
    return loop;
}

// Circles of radius r(z) at `levels` z levels evenly from z0 to z1.
SectionStack circle_stack(double z0, double z1, int levels, double r0, double r1) {
    SectionStack stack;
    for (int k = 0; k < levels; ++k) {
        const double t = double(k) / (levels - 1);
        stack.sections.push_back({z0 + t * (z1 - z0), {circle(r0 + t * (r1 - r0))}});
    }
    return stack;
}

// Radius where u changes sign along +x at height z.
double zero_crossing(const ImplicitFunction& u, double z, const Vec2& direction) {
    double inside = 0, outside = 3;
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (inside + outside);
        (u.value(Vec3(mid * direction.x(), mid * direction.y(), z)) < 0 ? inside : outside) = mid;
    }
    return 0.5 * (inside + outside);
}

TEST(CrossSectionSdf, CylinderSideIsTheDistanceAtMidHeight) {
    const CrossSectionSdf sdf(circle_stack(0, 2, 11, 1, 1));
    double worst = 0;
    for (double z : {1.0, 0.95, 1.13}) {
        for (double r = 0; r <= 2; r += 0.01) {
            const Vec3 p(r * std::cos(0.3), r * std::sin(0.3), z);
            const double exact = std::max({r - 1, z - 2, -z});  // inside: nearest of side, caps
            worst = std::max(worst, std::abs(sdf.value(p) - exact));
        }
    }
    EXPECT_LT(worst, 1e-3);
    std::printf("cylinder: max |u - exact distance| at mid-height: %.2e\n", worst);
}

TEST(CrossSectionSdf, CylinderCapsAreRight) {
    const CrossSectionSdf sdf(circle_stack(0, 2, 11, 1, 1));
    EXPECT_NEAR(sdf.value(Vec3(0.3, 0.2, 2.5)), 0.5, 1e-12);      // above the top cap
    EXPECT_NEAR(sdf.value(Vec3(0, 0, -0.2)), 0.2, 1e-12);         // below the bottom cap
    EXPECT_NEAR(sdf.value(Vec3(0, 0.1, 1.9)), -0.1, 1e-12);       // inside, nearest the top
    EXPECT_NEAR(sdf.value(Vec3(0, 0, 0.05)), -0.05, 1e-12);       // inside, nearest the bottom
    EXPECT_NEAR(sdf.value(Vec3(2, 0, 3)), std::sqrt(2.0), 1e-4);  // outside the rim
    EXPECT_EQ(sdf.gradient(Vec3(0.3, 0.2, 2.5)), Vec3(0, 0, 1));
    EXPECT_EQ(sdf.gradient(Vec3(0.3, 0.2, -1)), Vec3(0, 0, -1));
    const Box3 b = sdf.bounds();
    EXPECT_NEAR(b.lo.x(), -1, 1e-12);
    EXPECT_NEAR(b.hi.y(), 1, 1e-4);
    EXPECT_EQ(b.lo.z(), 0);
    EXPECT_EQ(b.hi.z(), 2);
    std::vector<ImplicitFunction::Piece> pieces;
    sdf.active_pieces(Vec3(1, 0, 2), 1e-6, pieces);  // on the top rim: a crease
    EXPECT_EQ(pieces.size(), 2u);
}

TEST(CrossSectionSdf, FrustumRadiusIsInterpolatedBetweenSlices) {
    // r(z) = 1 - 0.5 z for z in [0, 1], slices every 0.1.
    const CrossSectionSdf sdf(circle_stack(0, 1, 11, 1, 0.5));
    double worst = 0;
    for (int k = 0; k < 10; ++k) {
        const double z = 0.1 * k + 0.05;
        for (double angle : {0.1, 1.7, 4.0})
            worst = std::max(
                worst, std::abs(zero_crossing(sdf, z, Vec2(std::cos(angle), std::sin(angle))) -
                                (1 - 0.5 * z)));
    }
    EXPECT_LT(worst, 1e-3);
    std::printf("frustum: max |r(u = 0) - r(z)| at mid-slice: %.2e\n", worst);
}

TEST(CrossSectionSdf, GradientIsTheDerivativeOfTheValue) {
    const CrossSectionSdf sdf(circle_stack(0, 1, 11, 1, 0.5));
    std::mt19937 rng(2);
    for (int k = 0; k < 200; ++k) {
        Vec3 p = test::random_in_box(rng, Vec3(-1.5, -1.5, -0.5), Vec3(1.5, 1.5, 1.5));
        if (std::abs(std::fmod(p.z() + 10, 0.1)) < 1e-4) continue;  // a slice: a kink in z
        const Vec3 g = sdf.gradient(p);
        EXPECT_LT((g - test::central_difference(sdf, p, 1e-7)).norm(), 1e-4) << p.transpose();
    }
}

TEST(CrossSectionSdf, HolesFollowTheEvenOddRule) {
    Section annulus{0, {circle(1.0), circle(0.5)}};
    EXPECT_NEAR(section_distance(annulus, Vec2(0.75, 0)), -0.25, 1e-4);
    EXPECT_NEAR(section_distance(annulus, Vec2(0.1, 0)), 0.4, 1e-4);
    EXPECT_NEAR(section_distance(annulus, Vec2(0, 1.5)), 0.5, 1e-4);
    Vec2 g;
    section_distance(annulus, Vec2(0.2, 0), &g);
    EXPECT_NEAR(g.x(), -1, 1e-4);  // towards the inner circle: out of the hole is inwards
}

TEST(CrossSectionSdf, RefusesBadStacks) {
    EXPECT_THROW(CrossSectionSdf(circle_stack(0, 1, 1, 1, 1)), std::invalid_argument);
    SectionStack unsorted = circle_stack(0, 1, 3, 1, 1);
    std::swap(unsorted.sections[0], unsorted.sections[2]);
    EXPECT_THROW(CrossSectionSdf{unsorted}, std::invalid_argument);
    SectionStack short_loop = circle_stack(0, 1, 3, 1, 1);
    short_loop.sections[1].loops[0].resize(2);
    EXPECT_THROW(CrossSectionSdf{short_loop}, std::invalid_argument);
}

}  // namespace
}  // namespace hexmesh

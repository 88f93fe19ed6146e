// Tests of project_to_surface, tangent_frame and intersect_ray; "on the surface" is always
// checked with a formula written here, not with the body's own value().
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

#include "surface/analytic.h"
#include "surface/csg.h"
#include "surface/projection.h"
#include "test_helpers.h"

namespace hexmesh {
namespace {

using test::random_in_box;
using test::random_unit_vector;

constexpr double h = 0.05;  // the cell size of the tests: tolerances are relative to it

// Zero exactly on the boundary of the box |x_i - c_i| <= a_i, negative inside.
double box_indicator(const Vec3& x, const Vec3& c, const Vec3& a) {
    return ((x - c).cwiseAbs() - a).maxCoeff();
}

// Same for the capped cylinder about the z axis through c.
double cylinder_indicator(const Vec3& x, const Vec3& c, double r, double half_height) {
    const Vec3 d = x - c;
    return std::max(std::hypot(d.x(), d.y()) - r, std::abs(d.z()) - half_height);
}

// The sphere with only value(): its gradient is the base class's central differences,
// which vanish at the centre and so exercise the safeguard.
class PlainSphere : public ImplicitFunction {
  public:
    double value(const Vec3& p) const override { return p.norm() - 1.0; }
    Box3 bounds() const override { return {Vec3::Constant(-1), Vec3::Constant(1)}; }
};

TEST(ProjectToSurface, SphereShell) {
    const double radius = 1.0;
    const Sphere sphere(Vec3::Zero(), radius);
    std::mt19937 rng(20);
    std::uniform_real_distribution<double> shell(0.5 * radius, 1.5 * radius);
    int max_iterations = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p = shell(rng) * random_unit_vector(rng);
        const Projection r = project_to_surface(sphere, p, h);
        ASSERT_TRUE(r.converged) << p.transpose();
        EXPECT_LT(r.residual, 1e-8 * h);
        EXPECT_LT(std::abs(r.point.norm() - radius), 1e-8 * h) << p.transpose();
        EXPECT_LT((r.point - radius * p.normalized()).norm(), 1e-8 * h);  // nearest point
        max_iterations = std::max(max_iterations, r.iterations);
    }
    EXPECT_LE(max_iterations, 2);  // an exact distance needs one step
}

TEST(ProjectToSurface, BoxShellWithEdgesAndCorners) {
    const Vec3 c(0.1, -0.2, 0.3), a(0.5, 0.4, 0.3);
    const Box box(c, a);
    std::mt19937 rng(21);
    std::vector<Vec3> starts;
    while (starts.size() < 1000) {  // shell between the half- and the 1.5-size boxes
        const Vec3 p = random_in_box(rng, c - 1.5 * a, c + 1.5 * a);
        if (((p - c).cwiseAbs() - 0.5 * a).maxCoeff() > 0) starts.push_back(p);
    }
    for (int corner = 0; corner < 8; ++corner) {  // near corners and edge midpoints
        const Vec3 s((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
        for (double offset : {-1e-3, -1e-7, 0.0, 1e-7, 1e-3, 0.2}) {
            for (int i = 0; i < 10; ++i) {
                const Vec3 jitter = offset * random_unit_vector(rng);
                starts.push_back(c + s.cwiseProduct(a) + jitter);
                Vec3 edge = s.cwiseProduct(a);
                edge[i % 3] = 0;
                starts.push_back(c + edge + jitter);
            }
        }
    }
    starts.push_back(c);  // the centre: every face is a nearest one
    for (const Vec3& p : starts) {
        const Projection r = project_to_surface(box, p, h);
        ASSERT_TRUE(r.converged) << p.transpose();
        EXPECT_LT(r.residual, 1e-8 * h);
        EXPECT_LT(std::abs(box_indicator(r.point, c, a)), 1e-8 * h) << p.transpose();
        EXPECT_NEAR((r.point - p).norm(), std::abs(box.value(p)), 1e-8 * h);  // nearest
    }
}

TEST(ProjectToSurface, CurvedBodiesLandOnTheirSurfaces) {
    const Vec3 axes(1.0, 0.6, 0.3);
    const Ellipsoid ellipsoid(Vec3::Zero(), axes);
    const Torus torus(Vec3::Zero(), 1.0, 0.3);
    std::mt19937 rng(22);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p = random_in_box(rng, -1.5 * axes, 1.5 * axes);
        const Projection r = project_to_surface(ellipsoid, p, h);
        ASSERT_TRUE(r.converged) << p.transpose();
        EXPECT_NEAR(r.point.cwiseQuotient(axes).norm(), 1.0, 1e-8 * h) << p.transpose();

        const Vec3 q = random_in_box(rng, Vec3(-1.5, -1.5, -0.5), Vec3(1.5, 1.5, 0.5));
        const Projection s = project_to_surface(torus, q, h);
        ASSERT_TRUE(s.converged) << q.transpose();
        const Vec3 x = s.point;
        EXPECT_NEAR(std::hypot(std::hypot(x.x(), x.y()) - 1.0, x.z()), 0.3, 1e-8 * h);
    }
}

TEST(ProjectToSurface, VanishingGradientFallsBack) {
    const PlainSphere sphere;
    const Projection r = project_to_surface(sphere, Vec3::Zero(), h);
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.point.norm(), 1.0, 1e-8 * h);
    EXPECT_TRUE(r.point.allFinite());
}

TEST(ProjectToSurface, RelaxationConvergesMoreSlowly) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    ProjectionOptions options;
    options.relaxation = 0.5;
    const Projection r = project_to_surface(sphere, Vec3(0.3, 0.2, 1.4), h, options);
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.iterations, 10);
    EXPECT_NEAR(r.point.norm(), 1.0, 1e-9 * h);
    options.max_iterations = 3;
    const Projection cut = project_to_surface(sphere, Vec3(0.3, 0.2, 1.4), h, options);
    EXPECT_FALSE(cut.converged);
    EXPECT_EQ(cut.iterations, 3);
}

TEST(ProjectToSurface, BoxUnionCylinderLandsOnTheUnionSurface) {
    const Vec3 bc(0, 0, 0), ba(1.0, 0.5, 0.5);
    const Vec3 cc(1.0, 0, 0);
    const double cr = 0.4, chh = 1.0;
    const Csg body(CsgOp::Union,
                   {std::make_shared<Box>(bc, ba), std::make_shared<Cylinder>(cc, cr, chh)});
    std::mt19937 rng(23);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p = random_in_box(rng, Vec3(-1.5, -0.8, -1.3), Vec3(1.8, 0.8, 1.3));
        const Projection r = project_to_surface(body, p, h);
        ASSERT_TRUE(r.converged) << p.transpose();
        const double on =
            std::min(box_indicator(r.point, bc, ba), cylinder_indicator(r.point, cc, cr, chh));
        EXPECT_LT(std::abs(on), 1e-8 * h) << p.transpose();
    }
}

// Steps that zigzag between two pieces (box face and carved sphere) or stall at spurious
// critical points far from a flat ellipsoid must still end on the surface.
TEST(ProjectToSurface, HardCasesFromFarAway) {
    const Vec3 ba(1.0, 0.5, 0.5), sc(0.5, 0.3, 0.2);
    const double sr = 0.6;
    const Csg carved(CsgOp::Difference,
                     {std::make_shared<Box>(Vec3::Zero(), ba), std::make_shared<Sphere>(sc, sr)});
    const Vec3 axes(2.0, 0.5, 0.1);
    const Ellipsoid flat(Vec3::Zero(), axes);
    std::mt19937 rng(26);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = random_in_box(rng, -3 * ba, 3 * ba);
        const Projection r = project_to_surface(carved, p, h);
        ASSERT_TRUE(r.converged) << p.transpose();
        const double on =
            std::max(box_indicator(r.point, Vec3::Zero(), ba), sr - (r.point - sc).norm());
        EXPECT_LT(std::abs(on), 1e-8 * h) << p.transpose();

        const Vec3 q = random_in_box(rng, -3 * axes, 3 * axes);
        const Projection s = project_to_surface(flat, q, h);
        ASSERT_TRUE(s.converged) << q.transpose();
        EXPECT_NEAR(s.point.cwiseQuotient(axes).norm(), 1.0, 1e-7 * h) << q.transpose();
    }
}

TEST(TangentFrame, OrthonormalAndTangent) {
    const Box box(Vec3::Zero(), Vec3(1.0, 0.5, 0.3));
    const Torus torus(Vec3::Zero(), 1.0, 0.3);
    std::mt19937 rng(24);
    for (const ImplicitFunction* u : {static_cast<const ImplicitFunction*>(&box),
                                      static_cast<const ImplicitFunction*>(&torus)}) {
        for (int i = 0; i < 500; ++i) {
            const Vec3 p = random_in_box(rng, Vec3::Constant(-1.5), Vec3::Constant(1.5));
            const TangentFrame f = tangent_frame(*u, p);
            const Vec3 g = u->gradient(p);
            EXPECT_NEAR(f.normal.norm(), 1.0, 1e-14);
            EXPECT_NEAR(f.t1.norm(), 1.0, 1e-14);
            EXPECT_NEAR(f.t2.norm(), 1.0, 1e-14);
            EXPECT_NEAR(f.t1.dot(f.t2), 0.0, 1e-14);
            EXPECT_NEAR(f.t1.dot(g), 0.0, 1e-14 * g.norm());
            EXPECT_NEAR(f.t2.dot(g), 0.0, 1e-14 * g.norm());
            EXPECT_LT((f.normal - g.normalized()).norm(), 1e-14);
            EXPECT_LT((f.t1.cross(f.t2) - f.normal).norm(), 1e-14);
        }
    }
}

TEST(IntersectRay, SphereFromTheCentre) {
    const Vec3 c(0.2, 0.1, -0.3);
    const double radius = 0.7;
    const Sphere sphere(c, radius);
    std::mt19937 rng(25);
    for (int i = 0; i < 200; ++i) {
        const Vec3 d = random_unit_vector(rng);
        const auto hit = intersect_ray(sphere, c, 3.0 * d, h);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR((*hit - c).norm(), radius, 1e-10);
        EXPECT_LT((*hit - (c + radius * d)).norm(), 1e-10);
    }
    for (int axis = 0; axis < 3; ++axis) {  // hits on the faces of the bounds
        const auto hit = intersect_ray(sphere, c, -Vec3::Unit(axis), h);
        ASSERT_TRUE(hit.has_value());
        EXPECT_LT((*hit - (c - radius * Vec3::Unit(axis))).norm(), 1e-10);
    }
}

TEST(IntersectRay, TorusAndConeFirstCrossing) {
    const Torus torus(Vec3::Zero(), 1.0, 0.25);
    auto hit = intersect_ray(torus, Vec3(1, 0, 0), Vec3(1, 0, 0), h);  // inside the tube
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - Vec3(1.25, 0, 0)).norm(), 1e-10);
    hit = intersect_ray(torus, Vec3(0, -1, 0), Vec3(0, 0, 1), h);  // up through the tube
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - Vec3(0, -1, 0.25)).norm(), 1e-10);
    hit = intersect_ray(torus, Vec3::Zero(), Vec3(0, 1, 0), h);  // from the hole: inner wall
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - Vec3(0, 0.75, 0)).norm(), 1e-10);
    EXPECT_FALSE(intersect_ray(torus, Vec3::Zero(), Vec3(0, 0, 1), h).has_value());

    const Vec3 c(0.5, 0.5, 0.5);
    const Cone cone(c, 1.0, 0.0, 1.0);  // slant 2 rho + z = 1 about c
    hit = intersect_ray(cone, c, Vec3(0, -1, 0), h);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - (c + Vec3(0, -0.5, 0))).norm(), 1e-10);
    hit = intersect_ray(cone, c, Vec3(0, 0, 1), h);  // the apex
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - (c + Vec3(0, 0, 1))).norm(), 1e-10);
    hit = intersect_ray(cone, c, Vec3(1, 0, -1), h);  // the base at rho = 1, z = -1
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - (c + Vec3(1, 0, -1))).norm(), 1e-10);
}

TEST(IntersectRay, MissesAndBadDirection) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    EXPECT_FALSE(intersect_ray(sphere, Vec3(2, 0, 0), Vec3(1, 0, 0), h).has_value());
    EXPECT_FALSE(intersect_ray(sphere, Vec3(2, 0, 0), Vec3(0, 1, 0), h).has_value());
    const auto hit = intersect_ray(sphere, Vec3(3, 0, 0), Vec3(-1, 0, 0), h);  // from outside
    ASSERT_TRUE(hit.has_value());
    EXPECT_LT((*hit - Vec3(1, 0, 0)).norm(), 1e-10);
    EXPECT_THROW(intersect_ray(sphere, Vec3::Zero(), Vec3::Zero(), h), std::invalid_argument);
}

}  // namespace
}  // namespace hexmesh

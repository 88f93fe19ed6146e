// Tests of the sharp features of implicit bodies: active pieces, crease / corner
// classification, crease tangents, projection onto creases and corners.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "surface/analytic.h"
#include "surface/csg.h"
#include "surface/implicit_features.h"
#include "surface/transform.h"
#include "test_helpers.h"

namespace hexmesh {
namespace {

const double pi = std::acos(-1.0);
constexpr double h = 0.05;        // the cell size of these tests
constexpr double tol = 1e-3 * h;  // classification tolerance

// |cos| of the angle between two non-zero vectors.
double alignment(const Vec3& a, const Vec3& b) {
    return std::abs(a.dot(b)) / (a.norm() * b.norm());
}

// A point within distance h of c (uniform radius along a random direction).
Vec3 perturbed(std::mt19937& rng, const Vec3& c) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    return c + h * unit(rng) * test::random_unit_vector(rng);
}

std::vector<ImplicitFunction::Piece> pieces_at(const ImplicitFunction& u, const Vec3& p) {
    std::vector<ImplicitFunction::Piece> out;
    u.active_pieces(p, tol, out);
    return out;
}

// Box [c - s, c + s]: an edge is given by the axis it runs along and the signs of the
// other two coordinates.
const Vec3 box_center(0.1, -0.2, 0.3);
const Vec3 box_half(1.0, 0.7, 0.5);

struct BoxEdge {
    int axis;
    Vec3 sign;  // +-1 on the two other axes, 0 on `axis`
};

std::vector<BoxEdge> box_edges() {
    std::vector<BoxEdge> edges;
    for (int axis = 0; axis < 3; ++axis)
        for (int s = 0; s < 4; ++s) {
            Vec3 sign = Vec3::Zero();
            sign[(axis + 1) % 3] = (s & 1) ? 1 : -1;
            sign[(axis + 2) % 3] = (s & 2) ? 1 : -1;
            edges.push_back({axis, sign});
        }
    return edges;
}

// The point of the edge at parameter t in [-1, 1] along it.
Vec3 box_edge_point(const BoxEdge& e, double t) {
    Vec3 local = e.sign.cwiseProduct(box_half);
    local[e.axis] = t * box_half[e.axis];
    return box_center + local;
}

TEST(ImplicitFeatures, DefaultPieceIsTheSmoothBody) {
    const Sphere ball(Vec3(1, 2, 3), 0.5);
    const Vec3 p(1.2, 2.1, 3.3);
    const auto pieces = pieces_at(ball, p);
    ASSERT_EQ(pieces.size(), 1u);
    EXPECT_EQ(pieces[0].value, ball.value(p));
    EXPECT_EQ(pieces[0].gradient, ball.gradient(p));
}

TEST(ImplicitFeatures, BoxEdgesAreCreasesAlongTheEdge) {
    const Box box(box_center, box_half);
    for (const BoxEdge& e : box_edges())
        for (double t : {-0.9, -0.3, 0.0, 0.6}) {
            const Vec3 p = box_edge_point(e, t);
            EXPECT_EQ(pieces_at(box, p).size(), 2u);
            EXPECT_EQ(classify_surface_point(box, p, tol), FeatureKind::crease) << p.transpose();
            const Vec3 tangent = crease_tangent(box, p, tol);
            EXPECT_NEAR(tangent.norm(), 1.0, 1e-15);
            EXPECT_GT(alignment(tangent, Vec3::Unit(e.axis)), 1 - 1e-15) << p.transpose();
        }
}

TEST(ImplicitFeatures, BoxCornersAreCornersAndFacesSmooth) {
    const Box box(box_center, box_half);
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 sign((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
        const Vec3 p = box_center + sign.cwiseProduct(box_half);
        EXPECT_EQ(pieces_at(box, p).size(), 3u);
        EXPECT_EQ(classify_surface_point(box, p, tol), FeatureKind::corner) << p.transpose();
        EXPECT_EQ(boundary_vertex_kind(classify_surface_point(box, p, tol)), VertexKind::corner);
    }
    // Face centres and a face point 10 tolerances from an edge are smooth; half a
    // tolerance from the edge it is still the crease.
    for (int axis = 0; axis < 3; ++axis)
        for (double s : {-1.0, 1.0}) {
            const Vec3 p = box_center + s * box_half[axis] * Vec3::Unit(axis);
            EXPECT_EQ(classify_surface_point(box, p, tol), FeatureKind::smooth);
            EXPECT_EQ(crease_tangent(box, p, tol), Vec3::Zero());
        }
    const Vec3 edge = box_edge_point(box_edges()[0], 0.2);  // along x at y-, z-
    EXPECT_EQ(classify_surface_point(box, edge + Vec3(0, 10 * tol, 0), tol), FeatureKind::smooth);
    EXPECT_EQ(classify_surface_point(box, edge + Vec3(0, 0.5 * tol, 0), tol), FeatureKind::crease);
}

TEST(ImplicitFeatures, ProjectionLandsOnTheBoxEdge) {
    const Box box(box_center, box_half);
    std::mt19937 rng(7);
    for (const BoxEdge& e : box_edges())
        for (int i = 0; i < 20; ++i) {
            std::uniform_real_distribution<double> along(-0.5, 0.5);
            const Vec3 p = perturbed(rng, box_edge_point(e, along(rng)));
            const Vec3 x = project_to_crease(box, p, h);
            for (int a = 0; a < 3; ++a) {
                if (a == e.axis) continue;
                EXPECT_NEAR(x[a], box_center[a] + e.sign[a] * box_half[a], 1e-12 * h)
                    << p.transpose();
            }
            EXPECT_LT((x - p).norm(), h);  // the nearest point of the edge line
        }
}

TEST(ImplicitFeatures, SnapToCornerLandsOnTheBoxCorner) {
    const Box box(box_center, box_half);
    std::mt19937 rng(11);
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 sign((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
        const Vec3 c = box_center + sign.cwiseProduct(box_half);
        for (int i = 0; i < 10; ++i)
            EXPECT_LT((snap_to_corner(box, perturbed(rng, c), h) - c).norm(), 1e-12 * h);
    }
}

TEST(ImplicitFeatures, CylinderRimsAreCreasesAlongTheCircle) {
    const Vec3 c(0.2, 0.1, -0.3);
    const double r = 0.8, half_height = 0.4;
    const Cylinder cylinder(c, r, half_height);
    std::mt19937 rng(3);
    for (double s : {-1.0, 1.0})
        for (int k = 0; k < 12; ++k) {
            const double angle = 2 * pi * (k + 0.3) / 12;
            const Vec3 radial(std::cos(angle), std::sin(angle), 0);
            const Vec3 rim = c + r * radial + s * half_height * Vec3::UnitZ();
            EXPECT_EQ(classify_surface_point(cylinder, rim, tol), FeatureKind::crease);
            const Vec3 circle_tangent(-radial.y(), radial.x(), 0);
            EXPECT_GT(alignment(crease_tangent(cylinder, rim, tol), circle_tangent), 1 - 1e-12);
            // Side and cap points nearby are smooth.
            EXPECT_EQ(classify_surface_point(cylinder, rim - 0.1 * s * Vec3::UnitZ(), tol),
                      FeatureKind::smooth);
            EXPECT_EQ(classify_surface_point(cylinder, rim - 0.1 * radial, tol),
                      FeatureKind::smooth);
            for (int i = 0; i < 5; ++i) {
                const Vec3 x = project_to_crease(cylinder, perturbed(rng, rim), h) - c;
                EXPECT_NEAR(std::hypot(x.x(), x.y()), r, 1e-12 * h);
                EXPECT_NEAR(x.z(), s * half_height, 1e-12 * h);
            }
        }
}

TEST(ImplicitFeatures, ConeRimIsACreaseAndApexACorner) {
    const Vec3 c(0, 0, 0.2);
    const Cone cone(c, 0.6, 0.0, 0.5);  // apex at the top
    const Vec3 apex = c + 0.5 * Vec3::UnitZ();
    EXPECT_EQ(classify_surface_point(cone, apex, tol), FeatureKind::corner);
    const Vec3 rim = c + Vec3(0.6 * std::cos(1.0), 0.6 * std::sin(1.0), -0.5);
    EXPECT_EQ(classify_surface_point(cone, rim, tol), FeatureKind::crease);
    EXPECT_GT(alignment(crease_tangent(cone, rim, tol), Vec3(-std::sin(1.0), std::cos(1.0), 0)),
              1 - 1e-12);
    EXPECT_EQ(classify_surface_point(cone, 0.5 * (rim + apex), tol), FeatureKind::smooth);
    std::mt19937 rng(5);
    for (int i = 0; i < 10; ++i) {
        const Vec3 x = project_to_crease(cone, perturbed(rng, rim), h) - c;
        EXPECT_NEAR(std::hypot(x.x(), x.y()), 0.6, 1e-12 * h);
        EXPECT_NEAR(x.z(), -0.5, 1e-12 * h);
    }
}

// Box (size 2, 2, 1.2 at the origin) united with a cylinder (radius 0.6, height 1.4,
// centre (0, 0, 0.5)) that sticks out of the box top along the circle z = 0.6, r = 0.6.
TEST(ImplicitFeatures, UnionCreaseWhereTheCylinderLeavesTheBox) {
    const auto box = std::make_shared<Box>(Vec3::Zero(), Vec3(1, 1, 0.6));
    const auto cylinder = std::make_shared<Cylinder>(Vec3(0, 0, 0.5), 0.6, 0.7);
    const Csg body(CsgOp::Union, {box, cylinder});
    std::mt19937 rng(17);
    for (int k = 0; k < 16; ++k) {
        const double angle = 2 * pi * (k + 0.1) / 16;
        const Vec3 radial(std::cos(angle), std::sin(angle), 0);
        const Vec3 p = 0.6 * radial + 0.6 * Vec3::UnitZ();
        EXPECT_EQ(classify_surface_point(body, p, tol), FeatureKind::crease) << p.transpose();
        EXPECT_GT(alignment(crease_tangent(body, p, tol), Vec3(-radial.y(), radial.x(), 0)),
                  1 - 1e-12);
        // The box top outside the circle and the cylinder side above it are smooth.
        EXPECT_EQ(classify_surface_point(body, p + 0.1 * radial, tol), FeatureKind::smooth);
        EXPECT_EQ(classify_surface_point(body, p + 0.1 * Vec3::UnitZ(), tol), FeatureKind::smooth);
        for (int i = 0; i < 5; ++i) {
            const Vec3 x = project_to_crease(body, perturbed(rng, p), h);
            EXPECT_NEAR(std::hypot(x.x(), x.y()), 0.6, 1e-12 * h) << p.transpose();
            EXPECT_NEAR(x.z(), 0.6, 1e-12 * h);
            EXPECT_NEAR(body.value(x), 0.0, 1e-12 * h);
        }
    }
    // The box's own edges and corners and the cylinder's top rim stay features.
    EXPECT_EQ(classify_surface_point(body, Vec3(1, 0.3, 0.6), tol), FeatureKind::crease);
    EXPECT_EQ(classify_surface_point(body, Vec3(1, 1, -0.6), tol), FeatureKind::corner);
    EXPECT_EQ(classify_surface_point(body, Vec3(0, 0.6, 1.2), tol), FeatureKind::crease);
}

// A hole drilled through a box: the rim of the hole is a concave crease (pieces negated).
TEST(ImplicitFeatures, DifferenceRimIsACrease) {
    const auto box = std::make_shared<Box>(Vec3::Zero(), Vec3(1, 1, 0.5));
    const auto drill = std::make_shared<Cylinder>(Vec3::Zero(), 0.4, 1.0);
    const Csg body(CsgOp::Difference, {box, drill});
    std::mt19937 rng(19);
    for (int k = 0; k < 8; ++k) {
        const double angle = 2 * pi * (k + 0.5) / 8;
        const Vec3 radial(std::cos(angle), std::sin(angle), 0);
        const Vec3 p = 0.4 * radial + 0.5 * Vec3::UnitZ();
        const auto pieces = pieces_at(body, p);
        ASSERT_EQ(pieces.size(), 2u);
        bool hole_normal_inward = false;  // the drilled wall's normal points into the hole
        for (const auto& piece : pieces)
            hole_normal_inward |=
                alignment(piece.gradient, radial) > 1 - 1e-12 && piece.gradient.dot(radial) < 0;
        EXPECT_TRUE(hole_normal_inward);
        EXPECT_EQ(classify_surface_point(body, p, tol), FeatureKind::crease);
        EXPECT_GT(alignment(crease_tangent(body, p, tol), Vec3(-radial.y(), radial.x(), 0)),
                  1 - 1e-12);
        EXPECT_EQ(classify_surface_point(body, p - 0.2 * Vec3::UnitZ(), tol), FeatureKind::smooth);
        for (int i = 0; i < 5; ++i) {
            const Vec3 x = project_to_crease(body, perturbed(rng, p), h);
            EXPECT_NEAR(std::hypot(x.x(), x.y()), 0.4, 1e-12 * h);
            EXPECT_NEAR(x.z(), 0.5, 1e-12 * h);
        }
    }
}

TEST(ImplicitFeatures, TransformedBoxKeepsItsEdgesRotated) {
    const Mat3 rotation = rotation_from_axis_angle(Vec3(1, 2, 3), 37);
    const Vec3 translation(0.3, -1.1, 0.7);
    const double scale = 1.7;
    const auto child = std::make_shared<Box>(box_center, box_half);
    const Transformed body(child, translation, rotation, scale);
    auto moved = [&](const Vec3& y) -> Vec3 { return translation + scale * (rotation * y); };
    std::mt19937 rng(23);
    for (const BoxEdge& e : box_edges()) {
        const Vec3 p = moved(box_edge_point(e, 0.25));
        EXPECT_EQ(classify_surface_point(body, p, tol), FeatureKind::crease);
        EXPECT_GT(alignment(crease_tangent(body, p, tol), rotation * Vec3::Unit(e.axis)),
                  1 - 1e-12);
        for (int i = 0; i < 5; ++i) {
            const Vec3 x = project_to_crease(body, perturbed(rng, p), h);
            // Back in the child's frame the point lies on the edge line.
            const Vec3 y = rotation.transpose() * (x - translation) / scale;
            for (int a = 0; a < 3; ++a) {
                if (a == e.axis) continue;
                EXPECT_NEAR(y[a], box_center[a] + e.sign[a] * box_half[a], 1e-12);
            }
        }
    }
    const Vec3 corner = moved(box_center + box_half);
    EXPECT_EQ(classify_surface_point(body, corner, tol), FeatureKind::corner);
    EXPECT_LT((snap_to_corner(body, perturbed(rng, corner), h) - corner).norm(), 1e-12);
    EXPECT_EQ(classify_surface_point(body, moved(box_center + Vec3(box_half.x(), 0.1, 0.2)), tol),
              FeatureKind::smooth);
}

TEST(ImplicitFeatures, SmoothBodiesHaveNoFeatures) {
    const Sphere ball(Vec3(0.1, 0.2, 0.3), 0.8);
    const Ellipsoid egg(Vec3(-0.2, 0, 0.1), Vec3(1.0, 0.6, 0.4));
    std::mt19937 rng(29);
    for (int i = 0; i < 50; ++i) {
        const Vec3 d = test::random_unit_vector(rng);
        const Vec3 on_ball = Vec3(0.1, 0.2, 0.3) + 0.8 * d;
        EXPECT_EQ(classify_surface_point(ball, on_ball, tol), FeatureKind::smooth);
        EXPECT_EQ(crease_tangent(ball, on_ball, tol), Vec3::Zero());
        // Without a crease the projection falls back to the surface.
        const Vec3 x = project_to_crease(ball, perturbed(rng, on_ball), h);
        EXPECT_LT(std::abs(ball.value(x)), 1e-9 * h);
        const Vec3 on_egg = Vec3(-0.2, 0, 0.1) + d.cwiseProduct(Vec3(1.0, 0.6, 0.4)) / d.norm();
        EXPECT_EQ(classify_surface_point(egg, on_egg, tol), FeatureKind::smooth);
        EXPECT_EQ(boundary_vertex_kind(classify_surface_point(egg, on_egg, tol)), VertexKind::slip);
    }
}

}  // namespace
}  // namespace hexmesh

// Tests of the crease polylines of implicit bodies: which creases are found, that their points
// lie on them, that open polylines end bitwise at the corners and loops close bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "surface/analytic.h"
#include "surface/crease_curves.h"
#include "surface/csg.h"
#include "surface/transform.h"

namespace hexmesh {
namespace {

const double pi = std::acos(-1.0);
constexpr double step = 0.05;
using Polyline = std::vector<Vec3>;

double length(const Polyline& line) {
    double sum = 0;
    for (std::size_t i = 1; i < line.size(); ++i) sum += (line[i] - line[i - 1]).norm();
    return sum;
}

bool is_closed(const Polyline& line) {
    return line.front() == line.back();
}

// Index of the corner bitwise equal to p, -1 if none.
int corner_index(const CreaseCurves& curves, const Vec3& p) {
    const auto found = std::find(curves.corners.begin(), curves.corners.end(), p);
    return found == curves.corners.end() ? -1 : static_cast<int>(found - curves.corners.begin());
}

// What every result must satisfy: finite points, segments about `step` long, open polylines
// ending bitwise at two distinct corners, loops of at least 3 segments, distinct corners.
void expect_well_formed(const CreaseCurves& curves) {
    for (const Polyline& line : curves.polylines) {
        ASSERT_GE(line.size(), 2u);
        for (std::size_t i = 0; i < line.size(); ++i) {
            EXPECT_TRUE(line[i].allFinite());
            if (i == 0) continue;
            const double segment = (line[i] - line[i - 1]).norm();
            EXPECT_GT(segment, 0.25 * step - 1e-12);
            EXPECT_LT(segment, 2 * step);
        }
        if (is_closed(line)) {
            EXPECT_GE(line.size(), 4u);
        } else {
            const int a = corner_index(curves, line.front());
            const int b = corner_index(curves, line.back());
            EXPECT_GE(a, 0);
            EXPECT_GE(b, 0);
            EXPECT_NE(a, b);
        }
    }
    for (std::size_t i = 0; i < curves.corners.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            EXPECT_GT((curves.corners[i] - curves.corners[j]).norm(), 1e-3 * step);
}

int count_closed(const CreaseCurves& curves) {
    return static_cast<int>(
        std::count_if(curves.polylines.begin(), curves.polylines.end(), is_closed));
}

// Distance from p to the nearest edge of the box |x - c| <= half.
double distance_to_box_edges(const Vec3& p, const Vec3& c, const Vec3& half) {
    const Vec3 d = (p - c).cwiseAbs();
    double nearest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, e = (a + 2) % 3;
        const double across = std::hypot(d[b] - half[b], d[e] - half[e]);
        nearest = std::min(nearest, std::hypot(across, std::max(0.0, d[a] - half[a])));
    }
    return nearest;
}

// The box corners c + (+-half_x, +-half_y, +-half_z), moved by `move`.
template <class Move>
std::vector<Vec3> box_corners(const Vec3& c, const Vec3& half, Move move) {
    std::vector<Vec3> corners;
    for (int s = 0; s < 8; ++s)
        corners.push_back(
            move(c + Vec3(s & 1 ? 1 : -1, s & 2 ? 1 : -1, s & 4 ? 1 : -1).cwiseProduct(half)));
    return corners;
}

// Every expected corner is matched by exactly one found corner (within 1e-9) and vice versa.
void expect_corners(const CreaseCurves& curves, const std::vector<Vec3>& expected) {
    ASSERT_EQ(curves.corners.size(), expected.size());
    for (const Vec3& e : expected) {
        int matches = 0;
        for (const Vec3& c : curves.corners) matches += (c - e).norm() < 1e-9;
        EXPECT_EQ(matches, 1) << e.transpose();
    }
}

// The open polylines of a box: each on the box edges, from corner to an adjacent corner (the
// corners differ along one axis), all 12 edges once each; their total length the edges' sum.
template <class ToBox>
void expect_box_edges(const CreaseCurves& curves, const Vec3& c, const Vec3& half, ToBox to_box,
                      double scale) {
    std::set<std::pair<int, int>> edges;
    double total = 0;
    for (const Polyline& line : curves.polylines) {
        if (is_closed(line)) continue;
        for (const Vec3& p : line) EXPECT_LT(distance_to_box_edges(to_box(p), c, half), 1e-9);
        const Vec3 d = (to_box(line.back()) - to_box(line.front())).cwiseAbs();
        EXPECT_EQ((d.array() > 1e-9).count(), 1) << "not along one box edge";
        const int a = corner_index(curves, line.front()), b = corner_index(curves, line.back());
        edges.insert({std::min(a, b), std::max(a, b)});
        total += length(line);
    }
    EXPECT_EQ(edges.size(), 12u);
    EXPECT_NEAR(total, scale * 8 * half.sum(), 1e-9);
}

const auto identity = [](const Vec3& p) { return p; };

TEST(CreaseCurves, SmoothBodiesHaveNoCreases) {
    for (const Sphere& ball : {Sphere(Vec3(0.1, 0.2, 0.3), 0.8), Sphere(Vec3::Zero(), 0.3)}) {
        const CreaseCurves curves = trace_creases(ball, step);
        EXPECT_TRUE(curves.polylines.empty());
        EXPECT_TRUE(curves.corners.empty());
    }
    const CreaseCurves ring = trace_creases(Torus(Vec3::Zero(), 0.8, 0.3), step);
    EXPECT_TRUE(ring.polylines.empty());
    EXPECT_TRUE(ring.corners.empty());
}

TEST(CreaseCurves, BoxGivesItsTwelveEdgesAndEightCorners) {
    const Vec3 c(0.1, -0.2, 0.3), half(1.0, 0.7, 0.5);
    const CreaseCurves curves = trace_creases(Box(c, half), step);
    expect_well_formed(curves);
    expect_corners(curves, box_corners(c, half, identity));
    EXPECT_EQ(curves.polylines.size(), 12u);
    EXPECT_EQ(count_closed(curves), 0);
    expect_box_edges(curves, c, half, identity, 1.0);
}

TEST(CreaseCurves, CylinderGivesItsTwoRimsAsLoops) {
    const Vec3 c(0.2, 0.1, -0.3);
    const double radius = 0.7, half_height = 0.4;
    const CreaseCurves curves = trace_creases(Cylinder(c, radius, half_height), step);
    expect_well_formed(curves);
    EXPECT_TRUE(curves.corners.empty());
    ASSERT_EQ(curves.polylines.size(), 2u);
    double rim_z_sum = 0;
    for (const Polyline& line : curves.polylines) {
        EXPECT_TRUE(is_closed(line));
        EXPECT_NEAR(length(line), 2 * pi * radius, 0.01 * 2 * pi * radius);
        for (const Vec3& p : line) {
            EXPECT_NEAR(std::hypot(p.x() - c.x(), p.y() - c.y()), radius, 1e-9);
            EXPECT_NEAR(std::abs(p.z() - c.z()), half_height, 1e-9);
            EXPECT_EQ(p.z() > c.z(), line.front().z() > c.z()) << "a loop changes rims";
        }
        rim_z_sum += line.front().z() - c.z();
    }
    EXPECT_NEAR(rim_z_sum, 0, 1e-9) << "both loops on one rim";
}

// Edges shorter than the step hold no seed: they are traced from their corners.
TEST(CreaseCurves, ThinBoxKeepsItsShortEdges) {
    const Vec3 half(1, 1, 0.2 * step);
    const CreaseCurves curves = trace_creases(Box(Vec3::Zero(), half), step);
    expect_well_formed(curves);
    expect_corners(curves, box_corners(Vec3::Zero(), half, identity));
    ASSERT_EQ(curves.polylines.size(), 12u);
    int short_edges = 0;
    for (const Polyline& line : curves.polylines)
        if (line.size() == 2 && std::abs(length(line) - 0.4 * step) < 1e-12) ++short_edges;
    EXPECT_EQ(short_edges, 4);
    expect_box_edges(curves, Vec3::Zero(), half, identity, 1.0);
}

// cases/box_cylinder: the cylinder (radius 0.6, z in [-0.2, 1.2]) leaves the box top z = 0.6.
TEST(CreaseCurves, BoxCylinderUnionGivesBoxEdgesJunctionAndRim) {
    const Vec3 half(1, 1, 0.6);
    const auto box = std::make_shared<Box>(Vec3::Zero(), half);
    const auto cylinder = std::make_shared<Cylinder>(Vec3(0, 0, 0.5), 0.6, 0.7);
    const Csg body(CsgOp::Union, {box, cylinder});
    const CreaseCurves curves = trace_creases(body, step);
    expect_well_formed(curves);
    expect_corners(curves, box_corners(Vec3::Zero(), half, identity));
    EXPECT_EQ(curves.polylines.size(), 14u);
    ASSERT_EQ(count_closed(curves), 2);
    std::set<double> loop_heights;
    for (const Polyline& line : curves.polylines) {
        if (!is_closed(line)) continue;
        EXPECT_NEAR(length(line), 2 * pi * 0.6, 0.01 * 2 * pi * 0.6);
        for (const Vec3& p : line) {
            EXPECT_NEAR(std::hypot(p.x(), p.y()), 0.6, 1e-9);
            EXPECT_NEAR(p.z(), line.front().z(), 1e-9);
        }
        loop_heights.insert(std::round(line.front().z() * 10) / 10);
    }
    EXPECT_EQ(loop_heights, (std::set<double>{0.6, 1.2}));
    expect_box_edges(curves, Vec3::Zero(), half, identity, 1.0);
    // Same input, same output, bit for bit.
    const CreaseCurves again = trace_creases(body, step);
    EXPECT_EQ(again.corners, curves.corners);
    EXPECT_EQ(again.polylines, curves.polylines);
}

// A hole drilled through a box: the concave rims of the hole are two more loops.
TEST(CreaseCurves, DrilledBoxGivesBoxEdgesAndHoleRims) {
    const Vec3 half(1, 1, 0.5);
    const auto box = std::make_shared<Box>(Vec3::Zero(), half);
    const auto drill = std::make_shared<Cylinder>(Vec3::Zero(), 0.4, 1.0);
    const CreaseCurves curves = trace_creases(Csg(CsgOp::Difference, {box, drill}), step);
    expect_well_formed(curves);
    expect_corners(curves, box_corners(Vec3::Zero(), half, identity));
    EXPECT_EQ(curves.polylines.size(), 14u);
    ASSERT_EQ(count_closed(curves), 2);
    double rim_z_sum = 0;
    for (const Polyline& line : curves.polylines) {
        if (!is_closed(line)) continue;
        for (const Vec3& p : line) {
            EXPECT_NEAR(std::hypot(p.x(), p.y()), 0.4, 1e-9);
            EXPECT_NEAR(std::abs(p.z()), 0.5, 1e-9);
        }
        rim_z_sum += line.front().z();
    }
    EXPECT_NEAR(rim_z_sum, 0, 1e-9) << "both loops on one rim";
    expect_box_edges(curves, Vec3::Zero(), half, identity, 1.0);
}

TEST(CreaseCurves, TransformedBoxKeepsTwelveEdges) {
    const Vec3 c(0.1, -0.2, 0.3), half(0.5, 0.35, 0.25);
    const Mat3 rotation = rotation_from_axis_angle(Vec3(1, 2, 3), 37);
    const Vec3 translation(0.3, -1.1, 0.7);
    const double scale = 1.7;
    const Transformed body(std::make_shared<Box>(c, half), translation, rotation, scale);
    auto moved = [&](const Vec3& y) -> Vec3 { return translation + scale * (rotation * y); };
    auto to_box = [&](const Vec3& x) -> Vec3 {
        return rotation.transpose() * (x - translation) / scale;
    };
    const CreaseCurves curves = trace_creases(body, step);
    expect_well_formed(curves);
    expect_corners(curves, box_corners(c, half, moved));
    EXPECT_EQ(curves.polylines.size(), 12u);
    expect_box_edges(curves, c, half, to_box, scale);
}

// A frustum has two rim loops; a cone's apex is a corner that ends no polyline.
TEST(CreaseCurves, ConeRimsAndApex) {
    const CreaseCurves frustum = trace_creases(Cone(Vec3(0.1, 0, 0), 0.6, 0.3, 0.4), step);
    expect_well_formed(frustum);
    EXPECT_TRUE(frustum.corners.empty());
    ASSERT_EQ(frustum.polylines.size(), 2u);
    EXPECT_EQ(count_closed(frustum), 2);
    std::set<double> radii;
    for (const Polyline& line : frustum.polylines)
        radii.insert(std::round(std::hypot(line[0].x() - 0.1, line[0].y()) * 10) / 10);
    EXPECT_EQ(radii, (std::set<double>{0.3, 0.6}));

    const CreaseCurves cone = trace_creases(Cone(Vec3::Zero(), 0.5, 0, 0.5), step);
    expect_well_formed(cone);
    ASSERT_EQ(cone.corners.size(), 1u);
    EXPECT_LT((cone.corners[0] - Vec3(0, 0, 0.5)).norm(), 1e-9);
    ASSERT_EQ(cone.polylines.size(), 1u);
    EXPECT_TRUE(is_closed(cone.polylines[0]));
    EXPECT_NEAR(length(cone.polylines[0]), pi, 0.01 * pi);
    for (const Vec3& p : cone.polylines[0]) EXPECT_NEAR(p.z(), -0.5, 1e-9);
}

TEST(CreaseCurves, RejectsBadSteps) {
    const Box box(Vec3::Zero(), Vec3(1, 1, 1));
    EXPECT_THROW(trace_creases(box, 0), std::invalid_argument);
    EXPECT_THROW(trace_creases(box, -0.1), std::invalid_argument);
    EXPECT_THROW(trace_creases(box, std::nan("")), std::invalid_argument);
    EXPECT_THROW(trace_creases(box, 1e-4), std::invalid_argument);  // 2e4^3 lattice points
}

}  // namespace
}  // namespace hexmesh

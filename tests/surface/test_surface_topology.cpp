#include <gtest/gtest.h>

#include <cmath>

#include "sample_surfaces.h"
#include "surface/surface_topology.h"

using namespace hexmesh;

namespace {

TriangleSurface joined(TriangleSurface a, const TriangleSurface& b) {
    const int offset = int(a.points.size());
    a.points.insert(a.points.end(), b.points.begin(), b.points.end());
    for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    return a;
}

}  // namespace

TEST(SurfaceTopology, ASphereIsOneClosedPieceOfGenusZero) {
    const SurfaceTopology t = surface_topology(test::uv_sphere(Vec3::Zero(), 1, 16, 8));
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_EQ(t.components[0].euler, 2);
    EXPECT_EQ(t.components[0].genus, 0);
    EXPECT_EQ(t.components[0].boundary_edges, 0);
    EXPECT_EQ(t.non_manifold_edges, 0);
}

TEST(SurfaceTopology, ATorusHasOneHandle) {
    const SurfaceTopology t = surface_topology(test::torus_surface(1, 0.3, 24, 12));
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_EQ(t.components[0].euler, 0);
    EXPECT_EQ(t.components[0].genus, 1);
}

TEST(SurfaceTopology, TwoBodiesAreTwoComponentsLargestFirst) {
    const TriangleSurface two = joined(test::box_surface(Vec3::Zero(), Vec3::Ones(), 1),
                                       test::uv_sphere(Vec3(3, 0, 0), 1, 16, 8));
    const SurfaceTopology t = surface_topology(two);
    ASSERT_EQ(t.components.size(), 2u);
    EXPECT_EQ(t.components[0].triangles, 16 * 2 * (8 - 1));  // the sphere
    EXPECT_EQ(t.components[1].triangles, 12);                // the box
    EXPECT_NEAR(t.components[1].bounds.hi.x(), 1, 1e-12);
}

TEST(SurfaceTopology, HolesAreCountedAndCappedForTheGenus) {
    // A sphere without two of its triangles that share no point: two holes, genus 0 once capped.
    TriangleSurface s = test::uv_sphere(Vec3::Zero(), 1, 16, 8);
    s.triangles.erase(s.triangles.begin() + 40);
    s.triangles.erase(s.triangles.begin() + 2);
    const SurfaceTopology t = surface_topology(s);
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_EQ(t.components[0].boundary_edges, 6);
    EXPECT_EQ(t.components[0].boundary_loops, 2);
    EXPECT_EQ(t.components[0].genus, 0);
}

TEST(SurfaceTopology, TheWidestHoleIsMeasured) {
    EXPECT_EQ(surface_topology(test::uv_sphere(Vec3::Zero(), 1, 32, 16)).components[0].widest_hole,
              0);
    // The cap above z = 0.7 cut away: the hole's rim is the ring of latitude 45 degrees (its
    // points on the unit sphere at z = cos 45), whose bounds are a square 2 r across, r = sin 45.
    // A triangle cut from the southern half makes a narrower second hole.
    TriangleSurface s = test::without_cap(test::uv_sphere(Vec3::Zero(), 1, 32, 16), 0.7);
    s.triangles.erase(s.triangles.end() - 40);
    const SurfaceComponent c = surface_topology(s).components.at(0);
    EXPECT_EQ(c.boundary_loops, 2);
    const double r = std::sin(std::acos(-1.0) / 4);
    EXPECT_NEAR(c.widest_hole, 2 * std::sqrt(2.0) * r, 1e-12);
    EXPECT_NEAR((c.widest_hole_at - Vec3(0, 0, r)).norm(), 0, 1e-12);
}

TEST(SurfaceTopology, PointsAtTheSameCoordinatesAreOne) {
    // Every triangle with its own three points (an STL-like soup): still one closed sphere.
    const TriangleSurface s = test::uv_sphere(Vec3::Zero(), 1, 12, 6);
    TriangleSurface soup;
    for (const auto& t : s.triangles) {
        const int k = int(soup.points.size());
        for (int c = 0; c < 3; ++c) soup.points.push_back(s.points[t[c]]);
        soup.triangles.push_back({k, k + 1, k + 2});
    }
    const SurfaceTopology t = surface_topology(soup);
    ASSERT_EQ(t.components.size(), 1u);
    EXPECT_EQ(t.components[0].genus, 0);
    EXPECT_EQ(t.components[0].boundary_edges, 0);
}

// Exact distance (CGAL AABB tree, winding number) and surface diagnostics.
#include <gtest/gtest.h>

#include <optional>
#include <random>

#include "surface/exact_distance.h"
#include "surface/surface_diagnostics.h"
#include "surface/winding_number.h"
#include "tests/surface/sample_surfaces.h"
#include "tests/surface/test_helpers.h"

namespace hexmesh {
namespace {

TEST(ExactDistance, BoxDistanceClosestPointAndSign) {
    const TriangleSurface box = test::box_surface(Vec3::Zero(), Vec3(2, 1, 1), 2);
    const ExactDistance d(box);
    EXPECT_NEAR(d.distance(Vec3(3, 0.5, 0.5)), 1.0, 1e-12);
    EXPECT_NEAR(d.distance(Vec3(3, 2, 0.5)), std::sqrt(2.0), 1e-12);
    EXPECT_LT((d.closest_point(Vec3(3, 2, 0.5)) - Vec3(2, 1, 0.5)).norm(), 1e-12);
    EXPECT_NEAR(d.winding_number(Vec3(1, 0.5, 0.5)), 1.0, 1e-9);
    EXPECT_NEAR(d.winding_number(Vec3(3, 0.5, 0.5)), 0.0, 1e-9);
    EXPECT_NEAR(d.signed_distance(Vec3(1, 0.5, 0.2)), -0.2, 1e-12);
    EXPECT_NEAR(max_distance_to(d, {Vec3(1, 0.5, 0.5), Vec3(-1, 0, 0)}), 1.0, 1e-12);
}

TEST(ExactDistance, SphereMeshIsWithinItsChordSagOfTheSphere) {
    const TriangleSurface sphere = test::uv_sphere(Vec3::Zero(), 1.0, 64, 32);
    const ExactDistance d(sphere);
    std::mt19937 rng(6);
    for (int n = 0; n < 100; ++n) {
        const Vec3 p = 1.5 * test::random_unit_vector(rng);
        EXPECT_NEAR(d.distance(p), 0.5, 5e-3);  // sag of a 0.1 chord: 1.2e-3
        EXPECT_LT(d.signed_distance(0.3 * p), 0);
    }
}

TEST(SurfaceDiagnostics, ClosedSphereIsWatertight) {
    const TriangleSurface sphere = test::uv_sphere(Vec3(1, 1, 1), 2.0, 32, 16);
    const SurfaceDiagnostics d = diagnose_surface(sphere);
    EXPECT_EQ(d.triangles, 32 * 2 + 32 * 14 * 2);
    EXPECT_EQ(d.edges, 3 * d.triangles / 2);
    EXPECT_TRUE(d.watertight());
    EXPECT_NEAR(d.bounds.lo.z(), -1.0, 1e-12);
}

TEST(SurfaceDiagnostics, CountsHolesFinsFlipsDegenerateAndCrossings) {
    TriangleSurface s = test::box_surface(Vec3::Zero(), Vec3::Ones(), 2);  // 48 triangles
    s.triangles.erase(s.triangles.begin() + 5);                            // a hole: 3 open edges
    std::swap(s.triangles[20][0], s.triangles[20][1]);                     // one flipped facet
    const int a = s.triangles[30][0], b = s.triangles[30][1];
    s.points.push_back(0.5 * (s.points[a] + s.points[b]) + Vec3(0.3, 0.3, 0.3));  // a fin
    s.triangles.push_back({a, b, int(s.points.size()) - 1});
    s.triangles.push_back({a, a, b});  // repeated point
    const TriangleSurface other = test::box_surface(Vec3::Constant(0.5), Vec3::Constant(1.5));
    const int offset = int(s.points.size());
    for (const Vec3& p : other.points) s.points.push_back(p);
    for (auto t : other.triangles)
        s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});

    const SurfaceDiagnostics d = diagnose_surface(s);
    EXPECT_EQ(d.degenerate_triangles, 1);
    EXPECT_EQ(d.degenerate_ids, std::vector<int>{48});
    EXPECT_EQ(d.boundary_edges, 3 + 2);  // the hole, the fin's two free edges
    EXPECT_EQ(d.non_manifold_edges, 1);  // the fin's root
    EXPECT_EQ(d.inconsistent_edges, 3);  // the flipped facet's three edges
    EXPECT_GT(d.self_intersections, 0);  // the second box crosses the first
    EXPECT_FALSE(d.watertight());
}

TEST(SurfaceDiagnostics, SeparateBoxesDoNotIntersect) {
    TriangleSurface s = test::box_surface(Vec3::Zero(), Vec3::Ones());
    const TriangleSurface other = test::box_surface(Vec3::Constant(2), Vec3::Constant(3));
    for (const Vec3& p : other.points) s.points.push_back(p);
    for (auto t : other.triangles) s.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
    EXPECT_EQ(diagnose_surface(s).self_intersections, 0);
    EXPECT_TRUE(diagnose_surface(s).watertight());
}

}  // namespace
}  // namespace hexmesh

namespace hexmesh {
namespace {

// A closed box surface with a needle (three points on a line: an edge split at its middle on
// one side only, the gap filled by a flat triangle) and a triangle with a repeated point: both
// removed, the surface closed and oriented as before (every edge used once each way), its
// volume unchanged. Without a surface to keep (a lone flat triangle) there is no answer.
TEST(SurfaceDiagnostics, ZeroAreaTrianglesAreRemovedKeepingTheSurfaceClosed) {
    const TriangleSurface box = test::box_surface(Vec3::Zero(), Vec3(2, 1, 1), 2);
    const double volume = signed_volume(box);
    const TriangleSurface s = test::with_zero_area_triangles(box);
    ASSERT_EQ(diagnose_surface(s).degenerate_triangles, 2);
    long long removed = 0;
    const std::optional<TriangleSurface> fixed = without_zero_area_triangles(s, removed);
    ASSERT_TRUE(fixed.has_value());
    EXPECT_EQ(removed, 2);
    const SurfaceDiagnostics after = diagnose_surface(*fixed);
    EXPECT_TRUE(after.watertight());
    EXPECT_EQ(after.degenerate_triangles, 0);
    EXPECT_NEAR(signed_volume(*fixed), volume, 1e-12);
    // A surface without zero-area triangles comes back as it was.
    ASSERT_TRUE(without_zero_area_triangles(box, removed).has_value());
    EXPECT_EQ(removed, 0);
    TriangleSurface flat;
    flat.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    flat.triangles = {{0, 1, 2}};
    EXPECT_FALSE(without_zero_area_triangles(flat, removed).has_value());
}

TEST(WindingNumber, FastAgreesWithTheExactSum) {
    TriangleSurface sphere = test::uv_sphere(Vec3::Zero(), 1.0, 64, 32);
    sphere.triangles.resize(sphere.triangles.size() - 64);  // the south cap: a hole
    const WindingNumber fast(sphere);
    const ExactDistance exact(sphere);
    std::mt19937 rng(7);
    double worst = 0;
    for (int n = 0; n < 300; ++n) {
        const Vec3 p = test::random_in_box(rng, Vec3::Constant(-1.5), Vec3::Constant(1.5));
        worst = std::max(worst, std::abs(fast(p) - exact.winding_number(p)));
    }
    EXPECT_LT(worst, 0.05);                 // first-order clusters at accuracy 2 (measured 0.027)
    EXPECT_GT(fast(Vec3(0, 0, 0.5)), 0.9);  // inside, away from the hole
    EXPECT_LT(fast(Vec3(0, 0, 1.5)), 0.1);
}

}  // namespace
}  // namespace hexmesh

// Signed distance from a triangle surface (OpenVDB) against the exact distance (CGAL).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "surface/exact_distance.h"
#include "surface/mesh_sdf.h"
#include "surface/projection.h"
#include "tests/surface/sample_surfaces.h"
#include "tests/surface/test_helpers.h"

namespace hexmesh {
namespace {

// Unit sphere: 200 x 100 facets, edges ~0.03, chord sag < 1.3e-4; voxel 0.02.
class SphereSdf : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        surface_ = new TriangleSurface(test::uv_sphere(Vec3::Zero(), 1.0, 200, 100));
        MeshSdfOptions o;
        o.voxel_size = voxel;
        sdf_ = new MeshSdf(*surface_, o);
        exact_ = new ExactDistance(*surface_);
    }
    static void TearDownTestSuite() {
        delete sdf_;
        delete exact_;
        delete surface_;
    }
    static constexpr double voxel = 0.02;
    static inline TriangleSurface* surface_ = nullptr;
    static inline MeshSdf* sdf_ = nullptr;
    static inline ExactDistance* exact_ = nullptr;
};

TEST_F(SphereSdf, MatchesExactDistanceInTheBand) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> offset(-2 * voxel, 2 * voxel);  // band: 3 voxels
    double worst = 0;
    for (int n = 0; n < 2000; ++n) {
        const Vec3 p = (1 + offset(rng)) * test::random_unit_vector(rng);
        const double exact = exact_->signed_distance(p);
        worst = std::max(worst, std::abs(sdf_->value(p) - exact));
    }
    EXPECT_LT(worst, 0.5 * voxel);
    // The gradient is a unit normal in the band.
    for (int n = 0; n < 200; ++n) {
        const Vec3 dir = test::random_unit_vector(rng);
        const Vec3 g = sdf_->gradient((1 + offset(rng)) * dir);
        EXPECT_GT(g.normalized().dot(dir), 0.99);
        EXPECT_NEAR(g.norm(), 1.0, 0.05);
    }
}

TEST_F(SphereSdf, SignIsRightAndValueConservativeFarFromTheBand) {
    std::mt19937 rng(2);
    for (double r : {0.0, 0.3, 0.8, 1.2, 1.6, 3.0, 50.0}) {
        const Vec3 p = r * test::random_unit_vector(rng);
        const double u = sdf_->value(p), truth = r - 1;
        EXPECT_EQ(u < 0, truth < 0) << "r = " << r;
        EXPECT_LE(std::abs(u), std::abs(truth) + voxel) << "r = " << r;  // never overstates
    }
}

TEST_F(SphereSdf, ProjectionLandsOnTheSphere) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> radius(0.2, 2.5);
    double worst = 0;
    int failed = 0;
    for (int n = 0; n < 300; ++n) {
        const Vec3 start = radius(rng) * test::random_unit_vector(rng);
        const Projection q = project_to_surface(*sdf_, start, voxel);
        failed += !q.converged;
        worst = std::max(worst, std::abs(q.point.norm() - 1));
    }
    EXPECT_EQ(failed, 0);
    EXPECT_LT(worst, 0.1 * voxel);
}

TEST(MeshSdf, OpenSoupKeepsItsSignAwayFromTheHoles) {
    TriangleSurface soup = test::uv_sphere(Vec3::Zero(), 1.0, 120, 60);
    std::vector<Vec3> holes;
    for (int t : {500, 3000, 5100, 7000, 9000}) {  // single-facet holes, ~0.05 wide
        const auto& tri = soup.triangles[t];
        holes.push_back((soup.points[tri[0]] + soup.points[tri[1]] + soup.points[tri[2]]) / 3);
    }
    for (int t : {9000, 7000, 5100, 3000, 500}) soup.triangles.erase(soup.triangles.begin() + t);
    MeshSdfOptions o;
    o.voxel_size = 0.02;
    const MeshSdf sdf(soup, o);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> radius(0.0, 2.0);
    int checked = 0, wrong = 0;
    for (int n = 0; n < 3000; ++n) {
        const Vec3 p = radius(rng) * test::random_unit_vector(rng);
        if (std::abs(p.norm() - 1) < 0.02) continue;
        double to_hole = 1e9;
        for (const Vec3& h : holes) to_hole = std::min(to_hole, (p - h).norm());
        if (to_hole < 0.2) continue;
        ++checked;
        wrong += (sdf.value(p) < 0) != (p.norm() < 1);
    }
    EXPECT_GT(checked, 2000);
    EXPECT_EQ(wrong, 0);
}

TEST(MeshSdf, WideHoleIsSignedByWindingNumber) {
    TriangleSurface soup = test::uv_sphere(Vec3::Zero(), 1.0, 120, 60);
    TriangleSurface open = soup;
    open.triangles.clear();
    for (const auto& t : soup.triangles) {  // drop a cap of radius 0.3 (15 voxels) about +x
        const Vec3 c = (soup.points[t[0]] + soup.points[t[1]] + soup.points[t[2]]) / 3;
        if ((c - Vec3::UnitX()).norm() > 0.3) open.triangles.push_back(t);
    }
    MeshSdfOptions o;
    o.voxel_size = 0.02;
    const MeshSdf sdf(open, o);
    EXPECT_TRUE(sdf.signed_by_winding_number());
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> radius(0.0, 2.0);
    int checked = 0, wrong = 0;
    for (int n = 0; n < 3000; ++n) {
        const Vec3 p = radius(rng) * test::random_unit_vector(rng);
        if (std::abs(p.norm() - 1) < 0.02 || (p - Vec3::UnitX()).norm() < 0.8) continue;
        ++checked;
        wrong += (sdf.value(p) < 0) != (p.norm() < 1);
    }
    EXPECT_GT(checked, 2000);
    EXPECT_EQ(wrong, 0);
    // The flood fill leaks through such a hole: the reason for the winding number.
    o.sign = SdfSign::flood_fill;
    EXPECT_GT(MeshSdf(open, o).value(Vec3::Zero()), 0);
}

TEST(MeshSdf, VoxelSizeFromResolution) {
    const TriangleSurface box = test::box_surface(Vec3::Zero(), Vec3(4, 2, 1));
    MeshSdfOptions o;
    o.resolution = 64;
    const MeshSdf sdf(box, o);
    EXPECT_DOUBLE_EQ(sdf.voxel_size(), 4.0 / 64);
    EXPECT_GT(sdf.active_voxels(), 0);
    const double centre = sdf.value(Vec3(2, 1, 0.5));  // off the band: clamped, never deeper
    EXPECT_LT(centre, 0);
    EXPECT_GE(centre, -0.5);
    EXPECT_NEAR(sdf.value(Vec3(2, 1, 1.1)), 0.1, 0.05 * sdf.voxel_size());
}

}  // namespace
}  // namespace hexmesh

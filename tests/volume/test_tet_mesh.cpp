// Tests of the tet mesher (CGAL's Delaunay refinement of implicit bodies, creases protected)
// and of the removal of boundary caps.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/analytic.h"
#include "surface/crease_curves.h"
#include "volume/tet_mesh.h"

namespace hexmesh {
namespace {

const double pi = std::acos(-1.0);

TetMeshOptions uniform(double h) {
    TetMeshOptions o;
    o.size = [h](const Vec3&) { return h; };
    return o;
}

TEST(TetMesh, SphereIsFilledWithPositiveTetsAndItsSurfacePointsLieOnIt) {
    const Sphere sphere(Vec3(0.5, -1, 2), 1);
    const double h = 0.2;
    const TetMeshGeneration g = generate_tet_mesh(sphere, uniform(h));
    const TetMesh& m = g.refined.mesh;
    ASSERT_GT(m.num_cells(), 1000);
    ASSERT_EQ(g.refined.dimension.size(), m.points.size());
    EXPECT_FALSE(g.cgal_optimized);
    for (Id t = 0; t < m.num_cells(); ++t)
        ASSERT_GT(exact_orientation(m.points[m.node(t, 0)], m.points[m.node(t, 1)],
                                    m.points[m.node(t, 2)], m.points[m.node(t, 3)]),
                  0);
    int surface = 0;
    for (size_t v = 0; v < m.points.size(); ++v) {
        const double u = sphere.value(m.points[v]);
        if (g.refined.dimension[v] == 2) {
            ++surface;
            EXPECT_LT(std::abs(u), 1e-6 * h);
        } else {
            EXPECT_EQ(g.refined.dimension[v], 3);  // a smooth body: no crease, no corner
            EXPECT_LT(u, 0);
        }
    }
    EXPECT_GT(surface, 100);
    EXPECT_NEAR(signed_volume(m), 4 * pi / 3, 0.03 * 4 * pi / 3);
    // Deterministic: the same input gives the same mesh, bitwise.
    const TetMeshGeneration again = generate_tet_mesh(sphere, uniform(h));
    EXPECT_EQ(again.refined.mesh.points, m.points);
    EXPECT_EQ(again.refined.mesh.tets, m.tets);
}

TEST(TetMesh, BoxEdgesAndCornersAreProtected) {
    const Box box(Vec3::Zero(), Vec3(1, 0.7, 0.5));
    const double h = 0.2;
    TetMeshOptions o = uniform(h);
    o.features = trace_creases(box, 0.5 * h).polylines;
    ASSERT_EQ(o.features.size(), 12u);
    o.cgal_sliver_removal = true;
    const TetMeshGeneration g = generate_tet_mesh(box, o);
    for (const PlacedTetMesh* placed : {&g.refined, &*g.cgal_optimized}) {
        int corners = 0, on_edges = 0;
        for (size_t v = 0; v < placed->mesh.points.size(); ++v) {
            const Vec3 a = placed->mesh.points[v].cwiseAbs();
            const Vec3 gap = (a - Vec3(1, 0.7, 0.5)).cwiseAbs();
            const int faces = (gap.array() < 1e-9).count();
            if (placed->dimension[v] == 0) {
                ++corners;
                EXPECT_EQ(faces, 3) << placed->mesh.points[v].transpose();
            } else if (placed->dimension[v] == 1) {
                ++on_edges;
                EXPECT_EQ(faces, 2) << placed->mesh.points[v].transpose();
            }
        }
        EXPECT_EQ(corners, 8);
        EXPECT_GT(on_edges, 12 * 3);
        EXPECT_NEAR(signed_volume(placed->mesh), 2 * 1.4 * 1.0,
                    1e-6);  // flat faces, sharp edges: exact
    }
    // CGAL's sliver removal keeps the mesh valid and raises its smallest dihedral angle.
    EXPECT_EQ(measure_tet_quality(g.cgal_optimized->mesh).inverted, 0);
    EXPECT_GT(measure_tet_quality(g.cgal_optimized->mesh).min_dihedral,
              measure_tet_quality(g.refined.mesh).min_dihedral);
}

TEST(TetMesh, IsolatedCornerIsProtected) {
    // A pointed cone: its apex is a corner that ends no crease polyline.
    const Cone cone(Vec3::Zero(), 0.5, 0, 0.5);
    const double h = 0.1;
    const CreaseCurves creases = trace_creases(cone, 0.5 * h);
    TetMeshOptions o = uniform(h);
    o.features = creases.polylines;
    o.corners = creases.corners;
    const PlacedTetMesh placed = generate_tet_mesh(cone, o).refined;
    int apex = 0;
    for (size_t v = 0; v < placed.mesh.points.size(); ++v)
        if ((placed.mesh.points[v] - Vec3(0, 0, 0.5)).norm() < 1e-9)
            apex += placed.dimension[v] == 0;
    EXPECT_EQ(apex, 1);
}

TEST(TetMesh, SizingFunctionGradesTheMesh) {
    const Sphere sphere(Vec3::Zero(), 1);
    TetMeshOptions o;
    o.size = [&](const Vec3& x) { return std::min(0.4, 0.08 + 0.5 * std::abs(sphere.value(x))); };
    const TetMesh m = generate_tet_mesh(sphere, o).refined.mesh;
    // Mean edge length of the tets near the wall and near the centre.
    double wall = 0, core = 0;
    int n_wall = 0, n_core = 0;
    for (Id t = 0; t < m.num_cells(); ++t) {
        Vec3 c = Vec3::Zero();
        double edges = 0;
        for (int a = 0; a < 4; ++a) {
            c += 0.25 * m.points[m.node(t, a)];
            for (int b = a + 1; b < 4; ++b)
                edges += (m.points[m.node(t, a)] - m.points[m.node(t, b)]).norm() / 6;
        }
        if (c.norm() > 0.9) wall += edges, ++n_wall;
        if (c.norm() < 0.3) core += edges, ++n_core;
    }
    ASSERT_GT(n_wall, 0);
    ASSERT_GT(n_core, 0);
    EXPECT_LT(wall / n_wall, 0.15);
    EXPECT_GT(core / n_core, 2 * wall / n_wall);
}

TEST(TetMesh, MissingOrBadSizingIsRefused) {
    const Sphere sphere(Vec3::Zero(), 1);
    EXPECT_THROW(generate_tet_mesh(sphere, TetMeshOptions{}), std::invalid_argument);
    EXPECT_THROW(generate_tet_mesh(sphere, uniform(0)), std::invalid_argument);
}

TEST(TetMesh, BoundaryCapsAreRemovedAndOthersKept) {
    // Tet 0: the four corners of a square, one lifted a little (a flat cap) with every point
    // on the boundary. Tet 1: the same shape with one point inside the body. Tet 2: a fine
    // tet on the boundary.
    PlacedTetMesh placed;
    placed.mesh.points = {Vec3(0, 0, 0),  Vec3(1, 0, 0),  Vec3(0, 1, 0),  Vec3(1, 1, 0.05),
                          Vec3(5, 0, 0),  Vec3(6, 0, 0),  Vec3(5, 1, 0),  Vec3(6, 1, 0.05),
                          Vec3(10, 0, 0), Vec3(11, 0, 0), Vec3(10, 1, 0), Vec3(10, 0, 1)};
    placed.dimension = {2, 2, 2, 2, 2, 2, 2, 3, 2, 1, 1, 0};
    placed.mesh.tets = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    EXPECT_EQ(remove_boundary_caps(placed, 20), 1);
    ASSERT_EQ(placed.mesh.num_cells(), 2);
    ASSERT_EQ(placed.mesh.points.size(), 8u);  // the cap's points went with it
    EXPECT_EQ(placed.mesh.points[0], Vec3(5, 0, 0));
    EXPECT_EQ(placed.dimension[3], 3);
    EXPECT_EQ(placed.dimension[7], 0);
    // Nothing below 1 degree here: nothing goes.
    EXPECT_EQ(remove_boundary_caps(placed, 1), 0);
}

TEST(TetMesh, TetsAlongASharpCreaseAreNoCaps) {
    // Four boundary points, the small dihedral angle at the edge 01 that runs along a crease
    // (both ends of dimension 1): the angle is the body's own, the tet stays.
    PlacedTetMesh placed;
    placed.mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 1, 0.1)};
    placed.dimension = {1, 1, 2, 2};
    placed.mesh.tets = {0, 1, 2, 3};
    const auto angles = dihedral_angles({placed.mesh.points[0], placed.mesh.points[1],
                                         placed.mesh.points[2], placed.mesh.points[3]});
    ASSERT_LT(angles[0], 10);  // edge 01
    EXPECT_EQ(remove_boundary_caps(placed, 20), 0);
    placed.dimension = {2, 1, 2, 2};  // the same tet off the crease is a cap
    EXPECT_EQ(remove_boundary_caps(placed, 20), 1);
}

}  // namespace
}  // namespace hexmesh

// Tests of edge removal and 2-3 flips: same region, same boundary, positive tets, smallest dihedral
// angle never lowered.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/analytic.h"
#include "volume/tet_flips.h"
#include "volume/tet_mesh.h"

namespace hexmesh {
namespace {

// The faces used by one tet, as sorted point ids.
std::set<std::array<Id, 3>> boundary_faces(const TetMesh& m) {
    std::map<std::array<Id, 3>, int> uses;
    for (Id t = 0; t < m.num_cells(); ++t)
        for (int f = 0; f < 4; ++f) {
            std::array<Id, 3> key = {m.node(t, (f + 1) % 4), m.node(t, (f + 2) % 4),
                                     m.node(t, (f + 3) % 4)};
            std::sort(key.begin(), key.end());
            ++uses[key];
        }
    std::set<std::array<Id, 3>> out;
    for (const auto& [key, n] : uses)
        if (n == 1) out.insert(key);
    return out;
}

double smallest(const std::vector<Vec3>& x, std::array<Id, 4> t) {
    const auto a = dihedral_angles({x[t[0]], x[t[1]], x[t[2]], x[t[3]]});
    return *std::min_element(a.begin(), a.end());
}

TEST(TetFlips, DelaunayMeshOfASphereKeepsItsRegionAndBoundary) {
    const Sphere sphere(Vec3::Zero(), 1);
    TetMeshOptions o;
    o.size = [](const Vec3&) { return 0.2; };
    TetMesh mesh = generate_tet_mesh(sphere, o).refined.mesh;
    const double volume_before = signed_volume(mesh);
    const auto boundary_before = boundary_faces(mesh);
    const TetQualityReport before = measure_tet_quality(mesh);
    ASSERT_GT(before.slivers, 0);

    const FlipResult r = improve_by_flips(mesh, 30);
    EXPECT_GT(r.edge_removals + r.flips_23, 0);
    EXPECT_NEAR(signed_volume(mesh), volume_before, 1e-9 * volume_before);
    EXPECT_EQ(boundary_faces(mesh), boundary_before);
    const TetQualityReport after = measure_tet_quality(mesh);
    EXPECT_EQ(after.inverted, 0);
    EXPECT_GT(after.min_dihedral, before.min_dihedral);
    EXPECT_LT(after.slivers, before.slivers);
}

TEST(TetFlips, ThreeWedgesAroundAnEdgeBecomeTwo) {
    // The edge ab pierces the triangle cde close to c: the three tets around it are thin
    // wedges (smallest angle 14 degrees); the two tets on cde have 42.
    TetMesh mesh;
    mesh.points = {Vec3(0.6, 0, 1), Vec3(0.6, 0, -1), Vec3(1, 0, 0), Vec3(-0.5, 0.866, 0),
                   Vec3(-0.5, -0.866, 0)};
    mesh.tets = {0, 1, 2, 3, 0, 1, 3, 4, 0, 1, 4, 2};
    for (Id t = 0; t < 3; ++t)  // orient positively
        if (exact_orientation(mesh.points[mesh.tets[4 * t]], mesh.points[mesh.tets[4 * t + 1]],
                              mesh.points[mesh.tets[4 * t + 2]],
                              mesh.points[mesh.tets[4 * t + 3]]) < 0)
            std::swap(mesh.tets[4 * t + 2], mesh.tets[4 * t + 3]);
    const double old_angle = measure_tet_quality(mesh).min_dihedral;
    const double new_angle =
        std::min(smallest(mesh.points, {2, 3, 4, 0}), smallest(mesh.points, {2, 3, 4, 1}));
    ASSERT_GT(new_angle, old_angle);
    const FlipResult r = improve_by_flips(mesh, 60);
    EXPECT_EQ(r.edge_removals, 1);
    ASSERT_EQ(mesh.num_cells(), 2);
    EXPECT_NEAR(measure_tet_quality(mesh).min_dihedral, new_angle, 1e-9);
    EXPECT_EQ(measure_tet_quality(mesh).inverted, 0);
}

// The five tets around the edge (0, 1) of FiveTetsAroundAnEdgeBecomeSix, positively oriented.
TetMesh five_tets_around_an_edge() {
    TetMesh mesh;
    mesh.points = {Vec3(-0.17, 0.19, 0.95), Vec3(0.03, 0.09, -0.95), Vec3(-0.55, 0.39, 0.01),
                   Vec3(-1.1, 0, 0.18),     Vec3(-0.3, -0.44, 0.14), Vec3(0.54, -1.02, 0.1),
                   Vec3(0.83, -0.28, -0.06)};
    for (Id i = 0; i < 5; ++i) {
        std::array<Id, 4> t = {0, 1, 2 + i, 2 + (i + 1) % 5};
        if (exact_orientation(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]],
                              mesh.points[t[3]]) < 0)
            std::swap(t[2], t[3]);
        mesh.tets.insert(mesh.tets.end(), t.begin(), t.end());
    }
    return mesh;
}

TEST(TetFlips, FiveTetsAroundAnEdgeBecomeSix) {
    // The inner edge ab (points 0, 1) with a ring of five points around it: one of the five tets
    // around ab is a sliver (smallest angle 1.2 degrees). Removing ab leaves the ring's best
    // triangulation joined to a and to b: six tets, smallest angle 35.0 degrees.
    TetMesh mesh = five_tets_around_an_edge();
    const TetQualityReport before = measure_tet_quality(mesh);
    ASSERT_EQ(before.inverted, 0);
    ASSERT_LT(before.min_dihedral, 1.5);
    const double volume_before = signed_volume(mesh);
    const auto boundary_before = boundary_faces(mesh);
    const FlipResult r = improve_by_flips(mesh, 30);
    EXPECT_EQ(r.edge_removals, 1);
    ASSERT_EQ(mesh.num_cells(), 6);
    EXPECT_NEAR(measure_tet_quality(mesh).min_dihedral, 35.0, 0.01);
    EXPECT_EQ(measure_tet_quality(mesh).inverted, 0);
    EXPECT_NEAR(signed_volume(mesh), volume_before, 1e-12);
    EXPECT_EQ(boundary_faces(mesh), boundary_before);
}

TEST(TetFlips, OpenFanAroundABoundaryEdgeIsNotRemoved) {
    // Four of the five tets around the edge (0, 1): the edge is now on the boundary, its ring
    // of points does not close, and whatever flips happen keep the region and its boundary.
    for (Id dropped = 0; dropped < 5; ++dropped) {
        TetMesh mesh = five_tets_around_an_edge();
        mesh.tets.erase(mesh.tets.begin() + 4 * dropped, mesh.tets.begin() + 4 * dropped + 4);
        const double volume_before = signed_volume(mesh);
        const auto boundary_before = boundary_faces(mesh);
        const FlipResult r = improve_by_flips(mesh, 60);
        EXPECT_EQ(r.edge_removals, 0) << "dropped tet " << dropped;
        EXPECT_EQ(measure_tet_quality(mesh).inverted, 0);
        EXPECT_NEAR(signed_volume(mesh), volume_before, 1e-12);
        EXPECT_EQ(boundary_faces(mesh), boundary_before);
    }
}

TEST(TetFlips, TwoTetsWhoseApexEdgeMissesTheirFaceStay) {
    // The apexes' edge passes beside the shared face abc: three tets around it would overlap.
    TetMesh mesh;
    mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1.5, 1.5, 0.3),
                   Vec3(1.5, 1.5, -0.3)};
    mesh.tets = {0, 1, 2, 3, 0, 2, 1, 4};
    ASSERT_EQ(measure_tet_quality(mesh).inverted, 0);
    const std::vector<Id> before = mesh.tets;
    const FlipResult r = improve_by_flips(mesh, 60);
    EXPECT_EQ(r.edge_removals + r.flips_23, 0);
    EXPECT_EQ(mesh.tets, before);
}

TEST(TetFlips, MeshWithAnInvertedTetIsLeftAsItIs) {
    TetMesh mesh = five_tets_around_an_edge();
    std::swap(mesh.tets[2], mesh.tets[3]);  // the first tet inverted
    const std::vector<Id> before = mesh.tets;
    const FlipResult r = improve_by_flips(mesh, 60);
    EXPECT_EQ(r.edge_removals + r.flips_23, 0);
    EXPECT_EQ(mesh.tets, before);
}

TEST(TetFlips, TwoFlatTetsOnAWideFaceBecomeThree) {
    // Two flat tets on the wide triangle abc, apexes d and e 0.2 above and below its centre
    // (smallest angle 21.8 degrees); the three tets around the edge de have 43.6.
    TetMesh mesh;
    mesh.points = {Vec3(1, 0, 0), Vec3(-0.5, 0.866, 0), Vec3(-0.5, -0.866, 0), Vec3(0, 0, 0.2),
                   Vec3(0, 0, -0.2)};
    mesh.tets = {0, 1, 2, 3, 0, 2, 1, 4};
    ASSERT_EQ(measure_tet_quality(mesh).inverted, 0);
    double new_angle = 180;
    for (const std::array<Id, 4>& t : {std::array<Id, 4>{0, 1, 3, 4}, {1, 2, 3, 4}, {2, 0, 3, 4}})
        new_angle = std::min(new_angle, smallest(mesh.points, t));
    ASSERT_GT(new_angle, measure_tet_quality(mesh).min_dihedral + 20);
    const FlipResult r = improve_by_flips(mesh, 60);
    EXPECT_EQ(r.flips_23, 1);
    ASSERT_EQ(mesh.num_cells(), 3);
    EXPECT_NEAR(measure_tet_quality(mesh).min_dihedral, new_angle, 1e-9);
    EXPECT_EQ(measure_tet_quality(mesh).inverted, 0);
    EXPECT_NEAR(signed_volume(mesh), 2 * 0.2 * (3 * std::sqrt(3.0) / 4 * 1.0) / 3 * 1.0, 1e-3);
}

TEST(TetFlips, BoundaryFacesAreNeverFlipped) {
    // One tet alone: every face is on the boundary, nothing can change.
    TetMesh mesh;
    mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0.01)};
    mesh.tets = {0, 1, 2, 3};
    const FlipResult r = improve_by_flips(mesh, 60);
    EXPECT_EQ(r.edge_removals + r.flips_23, 0);
    EXPECT_EQ(mesh.tets, (std::vector<Id>{0, 1, 2, 3}));
}

// The smallest dihedral angle over the tets whose four points are all on the boundary.
double smallest_on_boundary(const TetMesh& m, const std::vector<bool>& on_boundary) {
    double angle = 180;
    for (Id t = 0; t < m.num_cells(); ++t) {
        bool pinned = true;
        for (int k = 0; k < 4; ++k) pinned = pinned && on_boundary[m.node(t, k)];
        if (pinned)
            angle = std::min(angle, smallest(m.points, {m.node(t, 0), m.node(t, 1), m.node(t, 2),
                                                        m.node(t, 3)}));
    }
    return angle;
}

// A slab thinner than the tets: most tets have their four points on its faces.
TEST(TetFlips, PointsInsertedInSliversOfBoundaryPointsRaiseTheirAngle) {
    const Box slab(Vec3::Zero(), Vec3(1, 1, 0.1));
    TetMeshOptions o;
    o.size = [](const Vec3&) { return 0.3; };
    const PlacedTetMesh placed = generate_tet_mesh(slab, o).refined;
    TetMesh mesh = placed.mesh;
    std::vector<bool> on_boundary(mesh.points.size());
    for (size_t v = 0; v < on_boundary.size(); ++v) on_boundary[v] = placed.dimension[v] < 3;
    const double before = smallest_on_boundary(mesh, on_boundary);
    ASSERT_LT(before, 10);  // four points on the faces: a sliver no move of them undoes
    const double volume = signed_volume(mesh);
    const auto boundary = boundary_faces(mesh);

    const Id inserted = insert_in_slivers(mesh, 15, on_boundary);
    EXPECT_GT(inserted, 0);
    ASSERT_EQ(mesh.points.size(), on_boundary.size() + size_t(inserted));
    EXPECT_NEAR(signed_volume(mesh), volume, 1e-9 * volume);
    EXPECT_EQ(boundary_faces(mesh), boundary);  // the new points are inside
    EXPECT_EQ(measure_tet_quality(mesh).inverted, 0);
    on_boundary.resize(mesh.points.size(), false);
    EXPECT_GT(smallest_on_boundary(mesh, on_boundary), before);
    for (size_t v = placed.mesh.points.size(); v < mesh.points.size(); ++v)
        EXPECT_LT(slab.value(mesh.points[v]), 0);
}

// A flat sliver of four boundary points (a square's corners, two 0.05 above its plane, two
// 0.05 below) with one tet on each face, its apex 0.5 out from the face's centroid. Each
// diagonal is a reflex edge of their union, so the points that see every face lie within
// 0.05 of both diagonals: every cone from them has a tet as flat as the sliver. Nothing is
// inserted and no flip applies.
TEST(TetFlips, NoPointInsertedWhereNoConeBeatsTheSliver) {
    TetMesh mesh;
    mesh.points = {Vec3(1, 0, 0.05), Vec3(0, 1, -0.05), Vec3(-1, 0, 0.05), Vec3(0, -1, -0.05)};
    auto add = [&](std::array<Id, 4> t) {
        if (signed_volume(
                {mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]}) < 0)
            std::swap(t[2], t[3]);
        mesh.tets.insert(mesh.tets.end(), t.begin(), t.end());
    };
    add({0, 1, 2, 3});
    for (Id i = 0; i < 4; ++i) {
        const Id a = (i + 1) % 4, b = (i + 2) % 4, c = (i + 3) % 4;
        const Vec3& pa = mesh.points[a];
        Vec3 n = (mesh.points[b] - pa).cross(mesh.points[c] - pa).normalized();
        if (n.dot(mesh.points[i] - pa) > 0) n = -n;
        mesh.points.push_back((pa + mesh.points[b] + mesh.points[c]) / 3 + 0.5 * n);
        add({a, b, c, Id(mesh.points.size()) - 1});
    }
    ASSERT_EQ(measure_tet_quality(mesh).inverted, 0);
    ASSERT_LT(measure_tet_quality(mesh).min_dihedral, 10);
    const TetMesh before = mesh;
    const FlipResult flips = improve_by_flips(mesh, 30);
    EXPECT_EQ(flips.edge_removals + flips.flips_23, 0);
    EXPECT_EQ(insert_in_slivers(mesh, 15, std::vector<bool>(8, true)), 0);
    EXPECT_EQ(mesh.points, before.points);
    EXPECT_EQ(mesh.tets, before.tets);
}

}  // namespace
}  // namespace hexmesh

// Tests of the tetmesh job: CGAL's Delaunay refinement of implicit and STL bodies with their
// creases protected, then the variational optimizer with slip, against CGAL's perturb + exude.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/tet_mesh_case.h"
#include "hexmesh/quality/tet_quality.h"
#include "surface/analytic.h"
#include "surface/implicit_features.h"

namespace hexmesh {
namespace {

const double pi = std::acos(-1.0);

TetCaseResult run(const std::string& json) {
    TetCaseOptions options;
    options.compare_cgal = true;
    options.cgal_sliver_bound = 25;  // CGAL's perturber pushed past its default 12 degrees
    std::ostringstream log;
    return run_tet_case(parse_case(json, "test.json"), options, log);
}

// What every optimized mesh must show against the refined mesh and CGAL's sliver removal.
void expect_better_than_cgal(const TetCaseResult& r) {
    ASSERT_TRUE(r.cgal);
    EXPECT_EQ(r.optimized.inverted, 0);
    EXPECT_EQ(r.optimized.slivers, 0);
    EXPECT_GT(r.refined.slivers, 0);  // there was something to remove
    EXPECT_GT(r.optimized.min_dihedral, r.cgal->min_dihedral)
        << "variational " << r.optimized.min_dihedral << " CGAL " << r.cgal->min_dihedral;
    EXPECT_LT(r.optimization.max_surface_distance, 1e-3 * r.wall_size);
    EXPECT_LT(r.optimization.max_crease_distance, 1e-3 * r.wall_size);
}

TEST(TetMeshCase, SphereBeatsCgalSliverRemoval) {
    const TetCaseResult r = run(
        R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}}, "tet_mesh": {"cell_size": 0.25}})");
    expect_better_than_cgal(r);
    EXPECT_EQ(r.crease_polylines, 0);
    EXPECT_NEAR(signed_volume(r.mesh), 4 * pi / 3, 0.03 * 4 * pi / 3);
}

TEST(TetMeshCase, CsgBodyKeepsItsCreasesAndCorners) {
    const std::string json = R"({"geometry": {"union": [
        {"box": {"center": [0, 0, 0], "size": [2, 2, 1.2]}},
        {"cylinder": {"center": [0, 0, 0.5], "radius": 0.6, "height": 1.4}}]},
        "tet_mesh": {"cell_size": 0.25}})";
    const TetCaseResult r = run(json);
    expect_better_than_cgal(r);
    EXPECT_EQ(r.crease_polylines, 14);  // 12 box edges, the cylinder's rim, where it leaves the box
    EXPECT_EQ(r.corners, 8);
    // Every box corner is a mesh point, exactly.
    int found = 0;
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) {
                const Vec3 corner(sx, sy, 0.6 * sz);
                for (const Vec3& p : r.mesh.points) found += (p - corner).norm() < 1e-9;
            }
    EXPECT_EQ(found, 8);
    // Both circular creases keep points exactly on them after the optimization.
    int on_top_rim = 0, on_junction = 0;
    for (const Vec3& p : r.mesh.points) {
        if (std::abs(std::hypot(p.x(), p.y()) - 0.6) > 1e-9) continue;
        on_top_rim += std::abs(p.z() - 1.2) < 1e-9;
        on_junction += std::abs(p.z() - 0.6) < 1e-9;
    }
    EXPECT_GE(on_top_rim, 12);  // circumference 3.8 at spacing about h = 0.25
    EXPECT_GE(on_junction, 12);
    const double exact = 2 * 2 * 1.2 + pi * 0.36 * 0.6;  // box + the cylinder above it
    EXPECT_NEAR(signed_volume(r.mesh), exact, 0.02 * exact);
}

// A closed cylinder (radius 0.5, height 1) of n side facets as an ASCII STL: sharp rims, a
// smooth side (neighbouring facets turn by 360 / n degrees).
void write_cylinder_stl(const std::string& path, int n) {
    std::ofstream out(path);
    out << "solid cylinder\n";
    auto facet = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        out << "facet normal 0 0 0\nouter loop\n";
        for (const Vec3& p : {a, b, c})
            out << "vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
        out << "endloop\nendfacet\n";
    };
    out.precision(17);
    auto rim = [&](int k, double z) {
        k %= n;  // the last facet closes on the first point, bitwise
        return Vec3(0.5 * std::cos(2 * pi * k / n), 0.5 * std::sin(2 * pi * k / n), z);
    };
    for (int k = 0; k < n; ++k) {
        facet(rim(k, 0), rim(k + 1, 0), rim(k + 1, 1));
        facet(rim(k, 0), rim(k + 1, 1), rim(k, 1));
        facet(Vec3(0, 0, 0), rim(k + 1, 0), rim(k, 0));
        facet(Vec3(0, 0, 1), rim(k, 1), rim(k + 1, 1));
    }
    out << "endsolid cylinder\n";
}

TEST(TetMeshCase, StlBodyKeepsItsSharpRims) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("hexmesh_tet_" + std::to_string(::getpid()) + ".stl");
    write_cylinder_stl(path.string(), 64);
    const TetCaseResult r = run(R"({"geometry": {"file": ")" + path.string() +
                                R"("}, "tet_mesh": {"cell_size": 0.12}})");
    std::filesystem::remove(path);
    expect_better_than_cgal(r);
    EXPECT_EQ(r.crease_polylines, 2);  // the two rims
    EXPECT_EQ(r.corners, 0);
}

TEST(TetMeshCase, GradedSizesFollowTheSizingFunction) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}},
        "tet_mesh": {"cell_size": 0.3, "wall_cell_size": 0.1, "grading": 0.5}})",
                              "test.json");
    const SizingFunction size = tet_sizing(c, make_body(c.geometry));
    EXPECT_NEAR(size(Vec3(1, 0, 0)), 0.1, 1e-12);
    EXPECT_NEAR(size(Vec3(0.8, 0, 0)), 0.2, 1e-9);
    EXPECT_NEAR(size(Vec3(0, 0, 0)), 0.3, 1e-12);
}

TEST(TetMeshCase, TangledMeshIsUntangledWithSlip) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}},
        "tet_mesh": {"cell_size": 0.25}})",
                              "test.json");
    const Body body = make_body(c.geometry);
    TetMeshOptions options;
    options.size = tet_sizing(c, body);
    PlacedTetMesh placed = generate_tet_mesh(*body, options).refined;
    // Interior points moved at random by up to 0.6 h along each axis: many tets fold.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> shift(-0.15, 0.15);
    for (size_t v = 0; v < placed.mesh.points.size(); ++v)
        if (placed.dimension[v] == 3)
            placed.mesh.points[v] += Vec3(shift(rng), shift(rng), shift(rng));
    ASSERT_GT(measure_tet_quality(placed.mesh).inverted, 50);

    const BoundaryGeometry boundary = case_boundary(c, body, 0.25);
    // Kinds from the mesh's own boundary faces, as for a tet mesh read from a file.
    const std::vector<VertexKind> kinds = boundary_kinds(placed.mesh, boundary, 1e-3 * 0.25);
    const untangle::UntangleOptions o = tet_untangle_options();
    const TetOptimization r = optimize_tet_mesh(placed.mesh, kinds, boundary, options.size, o);
    EXPECT_EQ(r.solve.inverted_after, 0);
    EXPECT_EQ(measure_tet_quality(placed.mesh).inverted, 0);
    EXPECT_LT(r.max_surface_distance, 1e-3 * 0.25);
    double off = 0;
    for (size_t v = 0; v < kinds.size(); ++v)
        if (kinds[v] == VertexKind::slip)
            off = std::max(off, std::abs(body->value(placed.mesh.points[v])));
    EXPECT_LT(off, 1e-9);
}

// Three tets, the first two sharing a vertex, the third apart, each optimized: the first made a
// sliver, the third turned inside out, the second moved a little. The sliver's and the inverted
// tet's vertices go back; the second keeps its moves except at the vertex it shares.
TEST(TetMeshCase, FallbackPositionsComeBackOnlyAroundTetsTheOptimizationMadeWorse) {
    TetMesh fallback;
    const auto regular = [&](const Vec3& at) {
        const Id first = Id(fallback.points.size());
        for (const Vec3& p : {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)})
            fallback.points.push_back(at + p);
        return first;
    };
    const Id a = regular(Vec3(0, 0, 0)), b = regular(Vec3(2, 2, 2)), c = regular(Vec3(10, 0, 0));
    fallback.points[b] = fallback.points[a];  // b's first vertex is a's first
    for (Id first : {a, b, c}) {
        for (int k = 0; k < 4; ++k) fallback.tets.push_back(first + k);
        const Id t = fallback.num_cells() - 1;
        if (signed_volume(
                {fallback.points[fallback.node(t, 0)], fallback.points[fallback.node(t, 1)],
                 fallback.points[fallback.node(t, 2)], fallback.points[fallback.node(t, 3)]}) < 0)
            std::swap(fallback.tets[size_t(4 * t + 2)], fallback.tets[size_t(4 * t + 3)]);
    }
    ASSERT_EQ(measure_tet_quality(fallback).inverted, 0);
    ASSERT_GT(measure_tet_quality(fallback).min_dihedral, 50);
    TetMesh optimized = fallback;
    optimized.points[a + 3] =
        Vec3(0, 0, -1);  // a: flat (a sliver), its vertex 3 on the plane of 1 and 2
    optimized.points[b + 2] += Vec3(0.05, -0.05, 0.02);        // b: a small move, still a good tet
    optimized.points[c + 3] = Vec3(10, 0, 0) + Vec3(1, 1, 3);  // c: through its opposite face
    const Id back = keep_fallback_where_worse(fallback, optimized, 30);
    EXPECT_EQ(back, 8);  // a's four (one of them b's first) and c's four
    for (Id v : {a, a + 1, a + 2, a + 3, c, c + 1, c + 2, c + 3})
        EXPECT_EQ(optimized.points[v], fallback.points[v]) << v;
    EXPECT_NE(optimized.points[b + 2], fallback.points[b + 2]);
    EXPECT_GE(measure_tet_quality(optimized).min_dihedral, 30);
    // A bound no tet of the optimized mesh falls under keeps every move.
    TetMesh all_good = fallback;
    all_good.points[b + 2] += Vec3(0.05, -0.05, 0.02);
    EXPECT_EQ(keep_fallback_where_worse(fallback, all_good, 30), 0);
}

// CGAL's refined mesh of a ball, its points moved to raise the smallest angle (no functional):
// every tet positive, the slivers gone, the surface points still on the sphere, a fixed point
// where it was.
TEST(TetMeshCase, WorstAnglesRaisedByMovingPointsOnTheSurfaceAndInside) {
    auto ball = std::make_shared<Sphere>(Vec3::Zero(), 1.0);
    TetMeshOptions o;
    o.size = [](const Vec3&) { return 0.25; };
    const PlacedTetMesh placed = generate_tet_mesh(*ball, o).refined;
    TetMesh mesh = placed.mesh;
    const TetQualityReport before = measure_tet_quality(mesh);
    ASSERT_GT(before.slivers, 0);
    std::vector<VertexKind> kinds = kinds_from_dimensions(placed.dimension);
    Id fixed = -1;
    for (size_t v = 0; v < kinds.size() && fixed < 0; ++v)
        if (kinds[v] == VertexKind::interior) fixed = Id(v), kinds[v] = VertexKind::fixed;
    const BoundaryGeometry boundary = BoundaryGeometry::implicit(ball, 1);

    EXPECT_GT(raise_smallest_angles(mesh, kinds, boundary, 15), 0);
    const TetQualityReport after = measure_tet_quality(mesh);
    EXPECT_EQ(after.inverted, 0);
    EXPECT_EQ(after.slivers, 0);
    EXPECT_GT(after.min_dihedral, 12) << "from " << before.min_dihedral;
    for (size_t v = 0; v < kinds.size(); ++v) {
        if (kinds[v] == VertexKind::slip) {
            EXPECT_NEAR(mesh.points[v].norm(), 1, 1e-6) << v;
        }
    }
    EXPECT_EQ(mesh.points[fixed], placed.mesh.points[fixed]);
    EXPECT_EQ(mesh.tets, placed.mesh.tets);
}

TEST(TetMeshCase, ExteriorDomainIsRefused) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}},
        "domain": "exterior"})",
                              "ext.json");
    std::ostringstream log;
    try {
        run_tet_case(c, {}, log);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("ext.json: domain: tetmesh meshes the body's interior"),
            std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace hexmesh

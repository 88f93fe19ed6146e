#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "grid_checks.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "surface/csg.h"
#include "surface/transform.h"
#include "volume/cube_sphere.h"
#include "volume/o_h_grid.h"

using namespace hexmesh;

namespace {

OHGridOptions sphere_options() {
    OHGridOptions o;
    o.cells_per_edge = 12;
    o.wall_cells = 8;
    o.wall_layers = {0.01, 1.2, 4};
    return o;
}

}  // namespace

TEST(OHGrid, SphereTopologyIsSevenConformingBlocks) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 1.0);
    const OHGridOptions o = sphere_options();
    const BlockGrid grid = make_o_h_grid(sphere, o);
    const int n = o.cells_per_edge, nk = o.wall_cells;
    ASSERT_EQ(grid.blocks.size(), 7u);
    EXPECT_EQ(grid.num_cells(), Id(n) * n * n + 6 * Id(n) * n * nk);
    const Id surface_nodes = 6 * Id(n) * n + 2;
    EXPECT_EQ(Id(grid.points.size()), Id(n + 1) * (n + 1) * (n + 1) + nk * surface_nodes);
    EXPECT_EQ(std::count(grid.kinds.begin(), grid.kinds.end(), VertexKind::slip), surface_nodes);
    // Conforming interfaces: the only faces used once are the 6 n^2 wall faces.
    const auto faces = test_support::count_faces(to_hex_mesh(grid));
    EXPECT_EQ(faces.boundary, 6 * Id(n) * n);
    EXPECT_EQ(faces.over_shared, 0);
}

TEST(OHGrid, LinesAreBuiltFromAGivenWallGrid) {
    // Wall nodes moved along the sphere: kept exactly, each line a straight segment from its
    // core node to its new wall node, the law's first height at the wall.
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 1.0);
    OHGridOptions o = sphere_options();
    BlockGrid moved = make_o_h_grid(sphere, o);
    const Mat3 turn = Eigen::AngleAxisd(0.04, Vec3(2, -1, 2).normalized()).toRotationMatrix();
    for (size_t v = 0; v < moved.points.size(); ++v)
        if (moved.kinds[v] == VertexKind::slip) moved.points[v] = c + turn * (moved.points[v] - c);
    o.wall_from = &moved.points;
    const BlockGrid grid = make_o_h_grid(sphere, o);
    const Block& b = grid.blocks[1];
    const int nk = o.wall_cells;
    for (int j = 0; j <= o.cells_per_edge; ++j)
        for (int i = 0; i <= o.cells_per_edge; ++i) {
            const Vec3 wall = grid.points[b.node(i, j, nk)], core = grid.points[b.node(i, j, 0)];
            EXPECT_EQ(wall, moved.points[b.node(i, j, nk)]);
            const Vec3 first = grid.points[b.node(i, j, nk - 1)];
            EXPECT_NEAR((first - wall).norm(), o.wall_layers.first_height, 1e-12);
            EXPECT_LT((first - wall).normalized().cross((core - wall).normalized()).norm(), 1e-12);
        }
    EXPECT_EQ(measure_quality(to_hex_mesh(grid)).inverted_corner_tets, 0);
    const std::vector<Vec3> fewer(moved.points.begin(), moved.points.end() - 1);
    o.wall_from = &fewer;
    EXPECT_THROW(make_o_h_grid(sphere, o), std::invalid_argument);
    // A wall node behind its core node (towards the centre): named, nothing built.
    std::vector<Vec3> behind = moved.points;
    const Id w = b.node(3, 4, nk);
    behind[w] = c + 0.1 * (behind[w] - c);
    o.wall_from = &behind;
    try {
        make_o_h_grid(sphere, o);
        ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("lies behind its core node"), std::string::npos)
            << e.what();
    }
}

TEST(OHGrid, LinesRunAlongGivenPathsThenStraightToTheCore) {
    // A wall placed without rays (the lattice on the sphere, a core cube of half-size 0.3) and
    // each node's path a bent polyline in to 0.6 of its radius, its level rising from 0 to 1:
    // every node of a line lies on its path or on the segment on to its core node, the first
    // layer along the path's first leg at the law's height, and one node of each line, the
    // same k for all, on the path's end (place_nodes_on_paths).
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions o = sphere_options();
    const CubeSurfaceLattice lattice = make_cube_surface_lattice(o.cells_per_edge);
    std::vector<Vec3> wall(lattice.size());
    for (Id s = 0; s < lattice.size(); ++s)
        wall[s] = cube_sphere_ray(lattice.points[s], o.cells_per_edge, Vec3::Ones()).normalized();
    o.wall_nodes = &wall;
    o.core_half = Vec3::Constant(0.3);
    const auto bend = [](const Vec3& w) {  // a point off the ray, between wall and 0.6 w
        return Vec3(0.8 * w + 0.05 * w.cross(Vec3(0.3, 0.5, 0.8)).normalized());
    };
    std::vector<Vec3> given_wall;
    o.paths = [&](const std::vector<Vec3>& at) {
        given_wall = at;
        WallPaths p;
        p.cells_per_edge = o.cells_per_edge;
        for (const Vec3& w : at) {
            p.lines.push_back({w, bend(w), 0.6 * w});
            p.levels.push_back({0.0, 0.5, 1.0});
        }
        return p;
    };
    const BlockGrid grid = make_o_h_grid(sphere, o);
    EXPECT_EQ(given_wall, wall);
    const auto distance_to_segment = [](const Vec3& x, const Vec3& a, const Vec3& b) {
        const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        return (x - (a + t * (b - a))).norm();
    };
    const int nk = o.wall_cells;
    std::set<int> k_at_end;
    for (const Block& b : grid.blocks) {
        if (b.name.rfind("wall_", 0) != 0) continue;
        for (int j = 0; j <= o.cells_per_edge; ++j)
            for (int i = 0; i <= o.cells_per_edge; ++i) {
                const Vec3 w = grid.points[b.node(i, j, nk)], core = grid.points[b.node(i, j, 0)];
                const std::vector<Vec3> polyline = {w, bend(w), 0.6 * w, core};
                for (int layer = 1; layer < nk; ++layer) {
                    const Vec3 x = grid.points[b.node(i, j, layer)];
                    double off = std::numeric_limits<double>::infinity();
                    for (size_t k = 1; k < polyline.size(); ++k)
                        off = std::min(off, distance_to_segment(x, polyline[k - 1], polyline[k]));
                    EXPECT_LT(off, 1e-12) << b.name << " " << i << " " << j << " " << layer;
                    if ((x - 0.6 * w).norm() < 1e-12) k_at_end.insert(nk - layer);
                }
                const Vec3 first = grid.points[b.node(i, j, nk - 1)];
                EXPECT_NEAR((first - w).norm(), o.wall_layers.first_height, 1e-12);
                EXPECT_LT((first - w).normalized().cross((bend(w) - w).normalized()).norm(), 1e-12);
            }
    }
    EXPECT_EQ(k_at_end.size(), 1u);
    EXPECT_EQ(measure_quality(to_hex_mesh(grid)).inverted_corner_tets, 0);
}

TEST(OHGrid, SphereGridIsValidWithWallNodesOnTheSphere) {
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GE(q.min_scaled_jacobian, 0.3);
    const double h = grid_length_scale(sphere, 12);
    for (size_t v = 0; v < grid.points.size(); ++v) {
        if (grid.kinds[v] == VertexKind::slip)
            EXPECT_LT(std::abs((grid.points[v] - c).norm() - 1.0), 1e-6 * h);
        else
            EXPECT_LT((grid.points[v] - c).norm(), 1.0 - 0.5 * 0.01);
    }
}

TEST(OHGrid, FirstLayerHasTheRequestedThicknessAndGrowth) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    const OHGridOptions o = sphere_options();
    const BlockGrid grid = make_o_h_grid(sphere, o);
    for (const Block& b : grid.blocks) {
        if (b.name == "core") continue;
        const int nk = b.nodes.nk - 1;
        for (int j = 0; j < b.nodes.nj; ++j)
            for (int i = 0; i < b.nodes.ni; ++i) {
                const Vec3 wall = grid.points[b.node(i, j, nk)];
                const Vec3 first = grid.points[b.node(i, j, nk - 1)];
                const Vec3 second = grid.points[b.node(i, j, nk - 2)];
                EXPECT_NEAR((wall - first).norm(), 0.01, 1e-9);
                EXPECT_NEAR((first - second).norm(), 0.012, 1e-9);
                // Radial lines: the first wall-normal line is orthogonal to the sphere.
                EXPECT_NEAR((wall - first).normalized().dot(wall.normalized()), 1.0, 1e-9);
            }
    }
}

TEST(OHGrid, EllipsoidGridIsValid) {
    const Ellipsoid body(Vec3::Zero(), Vec3(3, 2, 1));
    OHGridOptions o;
    o.cells_per_edge = 10;
    o.wall_cells = 6;
    const BlockGrid grid = make_o_h_grid(body, o);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, 0.2);
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip) {
            EXPECT_LT(std::abs(body.value(grid.points[v])), 1e-9);
        }
}

TEST(OHGrid, RaysThroughTheCornersOfABoxAreTheStretchedCubeSpheres) {
    const Vec3 half(1.0, 0.8, 0.6);
    CubeCorners corners;
    for (int c = 0; c < 8; ++c)
        for (int d = 0; d < 3; ++d) corners[c][d] = (c >> d & 1) ? half[d] : -half[d];
    const int n = 7;
    for (const LatticePoint& p : make_cube_surface_lattice(n).points)
        EXPECT_LT((cube_sphere_ray(p, n, corners) - cube_sphere_ray(p, n, half)).norm(), 1e-14);
}

namespace {

// The positions of the 8 patch corners of an O-H grid (node (0 or n, 0 or n) of each wall
// block's wall face), each once.
std::vector<Vec3> patch_corners(const BlockGrid& grid) {
    std::vector<Id> ids;
    for (const Block& b : grid.blocks) {
        if (b.face_patch[kmax] != "wall") continue;
        const int n = b.nodes.ni - 1, k = b.nodes.nk - 1;
        for (int j : {0, n})
            for (int i : {0, n}) ids.push_back(b.node(i, j, k));
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    std::vector<Vec3> points;
    for (Id v : ids) points.push_back(grid.points[v]);
    return points;
}

// Distance from p to the nearest of `points`.
double nearest(const std::vector<Vec3>& points, const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const Vec3& q : points) d = std::min(d, (q - p).norm());
    return d;
}

}  // namespace

TEST(OHGrid, PatchCornersGoToTheCornersOfABoxLikeBody) {
    // The box of cases/box_cylinder with its cylinder on top: the bounds' box reaches up to
    // the cylinder's top, so its diagonals miss the body's upper corners; the body's own
    // corners (one per octant around the bounds' centre) take the patch corners.
    const Body body = test_support::box_with_cylinder();
    OHGridOptions o = sphere_options();
    o.core_size = 0.3;
    const BlockGrid grid = make_o_h_grid(*body, o);
    const std::vector<Vec3> at = patch_corners(grid);
    ASSERT_EQ(at.size(), 8u);
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 0.6 : -0.6);
        EXPECT_LT(nearest(at, corner), 1e-9) << corner.transpose();
    }
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip) {
            EXPECT_LT(std::abs(body->value(grid.points[v])), 1e-9);
        }

    o.patch_corners_on_body_corners = false;  // the upper patch corners land on the cylinder
    const std::vector<Vec3> off = patch_corners(make_o_h_grid(*body, o));
    EXPECT_GT(nearest(off, Vec3(1.0, 1.0, 0.6)), 0.1);

    // A smooth body, or one with other corners than one per octant, keeps the bounds' box.
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 1.0);
    o.patch_corners_on_body_corners = true;
    const BlockGrid round = make_o_h_grid(sphere, o);
    o.patch_corners_on_body_corners = false;
    EXPECT_EQ(round.points, make_o_h_grid(sphere, o).points);
}

TEST(OHGrid, AnAxialCoreRunsRingsOfWallNodesAlongACylindersCircles) {
    // cases/box_cylinder: the rim (radius 0.6, z = 1.2) and the circle where the cylinder
    // leaves the box (z = 0.6) lie inside the top patch. Around the z axis, each is a ring of
    // wall nodes; with one core block the patch's lattice lines cross them.
    const Body body = test_support::box_with_cylinder();
    OHGridOptions o = sphere_options();
    o.core_size = 0.55;
    o.axis = 2;
    const BlockGrid grid = make_o_h_grid(*body, o);
    const int n = o.cells_per_edge, m = n - 2 * o.frame_cells;
    EXPECT_EQ(grid.blocks.size(), 51u);  // 13 core pieces, 13 per end, 3 per side
    EXPECT_EQ(measure_quality(to_hex_mesh(grid)).inverted_corner_tets, 0);
    EXPECT_EQ(test_support::count_faces(to_hex_mesh(grid)).over_shared, 0);
    auto on_circle = [&](const BlockGrid& g, double z) {
        int count = 0;
        for (size_t v = 0; v < g.points.size(); ++v) {
            const Vec3& p = g.points[v];
            if (g.kinds[v] == VertexKind::slip && std::abs(p.z() - z) < 1e-9 &&
                std::abs(std::hypot(p.x(), p.y()) - 0.6) < 1e-9)
                ++count;
        }
        return count;
    };
    EXPECT_EQ(on_circle(grid, 1.2), 4 * m);
    EXPECT_EQ(on_circle(grid, 0.6), 4 * m);
    o.axis = -1;
    const BlockGrid one_block = make_o_h_grid(*body, o);
    EXPECT_LT(on_circle(one_block, 1.2), 8);
    EXPECT_LT(on_circle(one_block, 0.6), 8);

    // Built again from its own wall, the grid is the same: the rings and patch corners are
    // found again from the wall and the body alone.
    o.axis = 2;
    o.wall_from = &grid.points;
    const BlockGrid again = make_o_h_grid(*body, o);
    ASSERT_EQ(again.points.size(), grid.points.size());
    for (size_t v = 0; v < grid.points.size(); ++v)
        EXPECT_LT((again.points[v] - grid.points[v]).norm(), 1e-9) << v;
}

TEST(OHGrid, TheAxisChosenIsTheOneTheCreasesRunAround) {
    OHGridOptions o = sphere_options();
    EXPECT_EQ(choose_o_h_axis(*test_support::box_with_cylinder(), o), 2);
    EXPECT_EQ(choose_o_h_axis(Sphere(Vec3(0.1, -0.2, 0.3), 1.0), o), -1);
    // Turned to lie along x, the cylinder's circles run around x.
    const Body along_x = std::make_shared<Transformed>(
        test_support::box_with_cylinder(), Vec3::Zero(),
        Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Vec3::UnitY()).toRotationMatrix());
    EXPECT_EQ(choose_o_h_axis(*along_x, o), 0);
    o.cells_per_edge = 2;  // no room for a frame: one core block
    EXPECT_EQ(choose_o_h_axis(*test_support::box_with_cylinder(), o), -1);
    EXPECT_EQ(make_o_h_grid(*test_support::box_with_cylinder(), o).blocks.size(), 7u);
}

TEST(OHGrid, RefusesACentreOutsideTheBody) {
    const Torus torus(Vec3::Zero(), 1.0, 0.3);  // its bounds' centre is in the hole
    EXPECT_THROW(make_o_h_grid(torus, OHGridOptions{}), std::invalid_argument);
}

TEST(OHGrid, RefusesABoundaryLayerThickerThanTheWallBlock) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OHGridOptions o = sphere_options();
    o.wall_layers = {0.2, 1.5, 6};
    EXPECT_THROW(make_o_h_grid(sphere, o), std::invalid_argument);
}

// A cross of three bars 0.3 thick is star-shaped around its centre, but the default core box
// (0.45 of the half extents) reaches out of the bars; the fitted core stays inside. A sphere's
// default core fits and is kept.
TEST(OHGrid, ACoreThatWouldReachTheWallIsFittedInside) {
    const Csg cross(CsgOp::Union,
                    std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(1, 0.15, 0.15)),
                                      std::make_shared<Box>(Vec3::Zero(), Vec3(0.15, 1, 0.15)),
                                      std::make_shared<Box>(Vec3::Zero(), Vec3(0.15, 0.15, 1))});
    OHGridOptions o;
    o.cells_per_edge = 8;
    o.wall_cells = 4;
    EXPECT_THROW(make_o_h_grid(cross, o), std::invalid_argument);
    o.core_size = core_size_within_wall(cross, o);
    EXPECT_LT(o.core_size, 0.15);
    const BlockGrid grid = make_o_h_grid(cross, o);
    for (Id id = 0; id < 9 * 9 * 9; ++id) EXPECT_LT(cross.value(grid.points[id]), 0) << id;

    OHGridOptions round;
    EXPECT_EQ(core_size_within_wall(Sphere(Vec3::Zero(), 1), round), 0.45);
}

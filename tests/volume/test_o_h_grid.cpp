#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

#include "grid_checks.h"
#include "hexmesh/core/quality.h"
#include "surface/analytic.h"
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
        EXPECT_NE(std::string(e.what()).find("lies behind its core node"), std::string::npos) << e.what();
    }
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

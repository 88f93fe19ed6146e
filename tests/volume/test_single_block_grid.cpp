#include <gtest/gtest.h>

#include <cmath>

#include "grid_checks.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "volume/single_block_grid.h"

using namespace hexmesh;

TEST(SingleBlockGrid, BoxBodyGivesAPerfectGridOnItsFaces) {
    const Box box(Vec3(1, 2, 3), Vec3(2.0, 1.0, 0.5));
    SingleBlockOptions o;
    o.cells = {8, 6, 4};
    const BlockGrid grid = make_single_block_grid(box, o);
    ASSERT_EQ(grid.blocks.size(), 1u);
    EXPECT_EQ(grid.num_cells(), 8 * 6 * 4);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_NEAR(q.min_scaled_jacobian, 1.0, 1e-9);
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip) {
            EXPECT_LT(std::abs(box.value(grid.points[v])), 1e-12);
        }
    EXPECT_EQ(test_support::count_faces(to_hex_mesh(grid)).boundary, 2 * (8 * 6 + 8 * 4 + 6 * 4));
}

TEST(SingleBlockGrid, WallLayersAtBothEndsOfEachLine) {
    const Box box(Vec3::Zero(), Vec3(1, 1, 1));
    SingleBlockOptions o;
    o.cells = {16, 16, 16};
    o.wall_layers = {0.01, 1.2, 4};
    const BlockGrid grid = make_single_block_grid(box, o);
    const Block& b = grid.blocks[0];
    const Vec3 p0 = grid.points[b.node(0, 8, 8)], p1 = grid.points[b.node(1, 8, 8)];
    const Vec3 q0 = grid.points[b.node(16, 8, 8)], q1 = grid.points[b.node(15, 8, 8)];
    EXPECT_NEAR((p1 - p0).norm(), 0.01, 1e-12);
    EXPECT_NEAR((q1 - q0).norm(), 0.01, 1e-12);
}

TEST(SingleBlockGrid, SphereCellsAtTheBoxCornersFold) {
    // The reason the O-H grid is the default for smooth bodies (docs/architecture.md#construction):
    // the three wall faces of each box-corner cell land on an almost flat piece of the sphere.
    const Sphere sphere(Vec3::Zero(), 1.0);
    SingleBlockOptions o;
    o.cells = {12, 12, 12};
    const BlockGrid grid = make_single_block_grid(sphere, o);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_cells, 8);
    EXPECT_LT(q.min_scaled_jacobian, 0.0);
}

// Structured blocks: flat indexing, cell corners, conversion to an unstructured hex mesh.
#include <gtest/gtest.h>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/mesh_quality.h"

namespace hexmesh {
namespace {

// One block of 4 x 3 x 3 nodes (3 x 2 x 2 cells) on the box [0,3] x [0,2] x [0,1].
BlockGrid small_box() {
    BlockGrid grid;
    Block block;
    block.name = "box";
    block.nodes = {4, 3, 3};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) {
                block.node_ids.push_back(static_cast<Id>(grid.points.size()));
                grid.points.emplace_back(i, j, 0.5 * k);
            }
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    grid.blocks.push_back(block);
    return grid;
}

TEST(BlockGrid, FlatIndexIsIFastest) {
    const Dims d{4, 3, 3};
    EXPECT_EQ(d.count(), 36);
    EXPECT_EQ(d.flat(1, 0, 0), 1);
    EXPECT_EQ(d.flat(0, 1, 0), 4);
    EXPECT_EQ(d.flat(0, 0, 1), 12);
    EXPECT_EQ(d.flat(3, 2, 2), 35);
}

TEST(BlockGrid, FlatIndexDoesNotOverflowOnLargeDims) {
    const Dims d{3000, 3000, 3000};
    EXPECT_EQ(d.count(), Id(27000000000));
    EXPECT_EQ(d.flat(2999, 2999, 2999), Id(27000000000) - 1);
}

TEST(BlockGrid, CountsOfSmallBox) {
    const BlockGrid grid = small_box();
    EXPECT_EQ(grid.blocks[0].cells().count(), 12);
    EXPECT_EQ(grid.num_cells(), 12);
    const HexMesh mesh = to_hex_mesh(grid);
    EXPECT_EQ(mesh.num_cells(), 12);
    EXPECT_EQ(mesh.num_points(), 36);
    EXPECT_EQ(mesh.hexes.size(), 96u);
}

TEST(BlockGrid, CellNodesFollowVtkOrder) {
    const BlockGrid grid = small_box();
    const auto n = cell_nodes(grid.blocks[0], 1, 1, 0);
    const auto& p = grid.points;
    // Node 0 at (1,1,0); the others are offset like the unit cube's VTK order.
    EXPECT_EQ(p[n[0]], Vec3(1, 1, 0));
    EXPECT_EQ(p[n[1]] - p[n[0]], Vec3(1, 0, 0));
    EXPECT_EQ(p[n[2]] - p[n[0]], Vec3(1, 1, 0));
    EXPECT_EQ(p[n[3]] - p[n[0]], Vec3(0, 1, 0));
    EXPECT_EQ(p[n[4]] - p[n[0]], Vec3(0, 0, 0.5));
    EXPECT_EQ(p[n[6]] - p[n[0]], Vec3(1, 1, 0.5));
}

TEST(BlockGrid, MeshCellsAreIFastestWithPositiveCornerDets) {
    const BlockGrid grid = small_box();
    const HexMesh mesh = to_hex_mesh(grid);
    const Block& b = grid.blocks[0];
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                const Id cell = b.cells().flat(i, j, k);
                EXPECT_EQ(cell, i + 3 * (j + 2 * k));
                for (int c = 0; c < 8; ++c)
                    EXPECT_EQ(mesh.node(cell, c), cell_nodes(b, i, j, k)[c]);
                EXPECT_EQ(mesh.corners(cell)[0], Vec3(i, j, 0.5 * k));
                for (double det : corner_determinants(mesh.corners(cell))) EXPECT_EQ(det, 0.5);
            }
}

TEST(BlockGrid, BlocksShareInterfaceNodes) {
    // Two 1-cell blocks side by side in x (lengths 1 and 2) sharing the 4 nodes of x = 1.
    BlockGrid grid;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) grid.points.emplace_back(i == 2 ? 3 : i, j, k);
    auto id = [](int i, int j, int k) { return Id(i + 3 * (j + 2 * k)); };
    for (int first : {0, 1}) {
        Block b;
        b.nodes = {2, 2, 2};
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) b.node_ids.push_back(id(first + i, j, k));
        grid.blocks.push_back(b);
    }
    const HexMesh mesh = to_hex_mesh(grid);
    EXPECT_EQ(mesh.num_cells(), 2);
    EXPECT_EQ(mesh.node(0, 1), mesh.node(1, 0));  // shared node (1,0,0)
    EXPECT_EQ(mesh.node(0, 6), mesh.node(1, 7));  // shared node (1,1,1)
    // The shared face is found from the node ids: it is the only internal face.
    EXPECT_DOUBLE_EQ(measure_quality(mesh).max_volume_ratio, 2.0);
    EXPECT_DOUBLE_EQ(measure_quality(grid).max_volume_ratio, 2.0);
}

TEST(BlockGrid, CellsNotHeldAreTheCellsAroundAFreeNode) {
    const BlockGrid grid = small_box();
    const HexMesh mesh = to_hex_mesh(grid);
    std::vector<bool> held(grid.points.size(), true);
    EXPECT_TRUE(cells_not_held(grid, held).empty());
    // Node (1, 1, 1) is a corner of the 8 cells with i, j, k in {0, 1}: ids i + 3 j + 6 k in
    // to_hex_mesh order (3 x 2 x 2 cells, i fastest).
    held[grid.blocks[0].node(1, 1, 1)] = false;
    const std::vector<std::array<Id, 8>> cells = cells_not_held(grid, held);
    ASSERT_EQ(cells.size(), 8u);
    const Id expected[] = {0, 1, 3, 4, 6, 7, 9, 10};
    for (size_t c = 0; c < cells.size(); ++c)
        for (int n = 0; n < 8; ++n) EXPECT_EQ(cells[c][n], mesh.node(expected[c], n));
    held.assign(grid.points.size(), false);
    EXPECT_EQ(Id(cells_not_held(grid, held).size()), mesh.num_cells());
}

}  // namespace
}  // namespace hexmesh

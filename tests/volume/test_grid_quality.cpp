// measure_quality(BlockGrid) reads the blocks directly, each face computed once; it must give
// the numbers of the unstructured path, measure_quality(to_hex_mesh(grid)), on every topology
// the toolkit builds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"
#include "volume/refine.h"
#include "volume/single_block_grid.h"

using namespace hexmesh;

namespace {

void expect_same_report(const BlockGrid& grid) {
    const QualityReport a = measure_quality(grid), b = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(a.cells, b.cells);
    EXPECT_EQ(a.inverted_corner_tets, b.inverted_corner_tets);
    EXPECT_EQ(a.inverted_cells, b.inverted_cells);
    // Same cells, same face owners: equal to rounding. A cell on a block boundary computes
    // its boundary faces from its own point order there (its neighbour's order here, for the
    // faces it does not own), and the mean's sum runs slab by slab there, in chunks here.
    const auto near = [](double x, double y) {
        return std::abs(x - y) <= 1e-12 * std::max(1.0, std::abs(y));
    };
    EXPECT_EQ(a.min_scaled_jacobian, b.min_scaled_jacobian);
    EXPECT_NEAR(a.mean_scaled_jacobian, b.mean_scaled_jacobian, 1e-14);
    EXPECT_PRED2(near, a.max_skewness, b.max_skewness);
    EXPECT_PRED2(near, a.max_non_orthogonality_deg, b.max_non_orthogonality_deg);
    EXPECT_PRED2(near, a.max_aspect_ratio, b.max_aspect_ratio);
    EXPECT_PRED2(near, a.max_volume_ratio, b.max_volume_ratio);
    EXPECT_PRED2(near, a.min_volume, b.min_volume);
}

// Moves every node by up to `amount` in each coordinate: cells inverted, faces skewed,
// interfaces between blocks no longer planar.
void shake(BlockGrid& grid, double amount, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-amount, amount);
    for (Vec3& p : grid.points) p += Vec3(d(rng), d(rng), d(rng));
}

OHGridOptions o_h_options() {
    OHGridOptions o;
    o.cells_per_edge = 6;
    o.wall_cells = 4;
    o.wall_layers = {0.02, 1.2, 2};
    return o;
}

TEST(GridQuality, OHGridOfAnEllipsoidMatchesTheUnstructuredReport) {
    const BlockGrid grid =
        make_o_h_grid(Ellipsoid(Vec3(0.1, 0, 0), Vec3(1.5, 1.0, 0.5)), o_h_options());
    expect_same_report(grid);
}

TEST(GridQuality, ShakenOHGridCountsTheSameInvertedCells) {
    BlockGrid grid = make_o_h_grid(Sphere(Vec3::Zero(), 1.0), o_h_options());
    shake(grid, 0.12, 7);
    const QualityReport q = measure_quality(grid);
    EXPECT_GT(q.inverted_cells, 0);
    EXPECT_LT(q.inverted_cells, q.cells);
    expect_same_report(grid);
}

TEST(GridQuality, OGridAroundASphereMatchesTheUnstructuredReport) {
    OGridOptions o;
    o.cells_per_edge = 5;
    o.layers = 7;
    o.wall_layers = {0.01, 1.2, 4};
    BlockGrid grid = make_o_grid(Sphere(Vec3::Zero(), 1.0), o);
    expect_same_report(grid);
    shake(grid, 0.05, 3);
    expect_same_report(grid);
}

TEST(GridQuality, SingleBlockAndRefinedGridsMatchTheUnstructuredReport) {
    SingleBlockOptions o;
    o.cells = {5, 4, 3};
    BlockGrid box = make_single_block_grid(Box(Vec3::Zero(), Vec3(1.0, 0.7, 0.4)), o);
    shake(box, 0.02, 11);
    expect_same_report(box);
    expect_same_report(refine_grid(make_o_h_grid(Sphere(Vec3::Zero(), 1.0), o_h_options())));
}

// A grid measured as it is made, one block at a time, each block with its own points and
// the whole grid's ids: the numbers of the whole grid's report.
TEST(GridQuality, BlocksMeasuredOneAtATimeMatchTheWholeGrid) {
    BlockGrid coarse = make_o_h_grid(Sphere(Vec3::Zero(), 1.0), o_h_options());
    shake(coarse, 0.03, 9);
    const QualityReport whole = measure_quality(refine_grid(coarse));
    BlockRefiner refiner(coarse);
    BlockQuality streamed;
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        const RefinedBlock piece = refiner.refine(b);
        streamed.add(piece.grid, piece.grid.blocks[0], &piece.ids);
    }
    const QualityReport q = streamed.report();
    EXPECT_EQ(q.cells, whole.cells);
    EXPECT_EQ(q.inverted_corner_tets, whole.inverted_corner_tets);
    EXPECT_EQ(q.min_scaled_jacobian, whole.min_scaled_jacobian);
    EXPECT_EQ(q.mean_scaled_jacobian, whole.mean_scaled_jacobian);  // same order of sums
    EXPECT_EQ(q.max_skewness, whole.max_skewness);
    EXPECT_EQ(q.max_non_orthogonality_deg, whole.max_non_orthogonality_deg);
    EXPECT_EQ(q.max_aspect_ratio, whole.max_aspect_ratio);
    EXPECT_EQ(q.max_volume_ratio, whole.max_volume_ratio);
    EXPECT_EQ(q.min_volume, whole.min_volume);
}

// A block one cell thick (every cell on both k faces), and an empty block (no nodes, as a
// reader may hand over) before a real one: ids of the later block's cells must not shift.
TEST(GridQuality, ThinAndEmptyBlocksMatchTheUnstructuredReport) {
    BlockGrid grid;
    Block thin;
    thin.nodes = {6, 5, 2};
    thin.face_patch = {"a", "b", "c", "d", "e", "f"};
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 6; ++i) {
                thin.node_ids.push_back(Id(grid.points.size()));
                grid.points.push_back(Vec3(0.2 * i, 0.15 * j, 0.1 * k));
            }
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    grid.blocks.push_back(thin);
    shake(grid, 0.01, 5);
    expect_same_report(grid);
    grid.blocks.insert(grid.blocks.begin(), Block{});
    EXPECT_EQ(grid.num_cells(), 5 * 4 * 1);
    EXPECT_EQ(measure_quality(grid).cells, 5 * 4 * 1);
    expect_same_report(grid);
}

// Three one-cell blocks over the same eight nodes: every face is listed by three cells.
TEST(GridQuality, FaceSharedByThreeBlocksIsRejected) {
    BlockGrid grid;
    for (int v = 0; v < 8; ++v) grid.points.push_back(Vec3(v & 1, (v >> 1) & 1, (v >> 2) & 1));
    grid.kinds.assign(8, VertexKind::interior);
    for (int b = 0; b < 3; ++b) {
        Block block;
        block.name = "copy" + std::to_string(b);
        block.nodes = {2, 2, 2};
        for (Id v = 0; v < 8; ++v) block.node_ids.push_back(v);
        grid.blocks.push_back(block);
    }
    try {
        measure_quality(grid);
        ADD_FAILURE() << "a face of three cells was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("more than two cells"), std::string::npos) << e.what();
    }
}

}  // namespace

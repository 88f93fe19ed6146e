// Nested families on the body: refine_on_body, refine_family and refine_blocks on the sphere
// and the bean STL; the refined wall law on the families `run` makes of the bundled cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>

#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/pipeline/run_case.h"
#include "hexmesh/pipeline/untangle_and_optimize.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_meter.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/wall_quality.h"
#include "io/grid_pictures.h"
#include "io/report_page.h"
#include "tests/scratch_registry.h"

using namespace hexmesh;

namespace {

struct Family {
    Body body;
    std::vector<BlockGrid> levels;
    std::vector<GridReport> reports;
};

// Three levels from a small O-H grid of `case_text`, level 1 optimized as `run` does.
Family make_family(const std::string& case_text) {
    const Case c = parse_case(case_text, "family.json");
    Family f;
    f.body = make_body(c.geometry);
    BlockGrid coarse = build_grid(c, *f.body);
    GridOptimizationOptions o;
    o.untangle.optimize_solver.method = untangle::Method::block_diagonal;
    o.untangle.max_optimize_iterations = 5;
    optimize_grid(coarse, *f.body, o);
    f.levels = refine_family(coarse, *f.body, 3);
    for (const BlockGrid& g : f.levels) f.reports.push_back(measure_grid(g, *f.body));
    return f;
}

const Family& family(const std::string& name) {
    static std::map<std::string, Family> cache;
    if (!cache.count(name)) {
        const std::string bean = std::string(HEXMESH_SOURCE_DIR) + "/cases/bean/bean.stl";
        cache[name] = make_family(
            name == "sphere" ? R"({"geometry": {"sphere": {"center": [0.1, 0, -0.2], "radius": 1}},
                     "grid": {"cells_per_edge": 6, "wall_cells": 4}})"
                             : R"({"geometry": {"file": ")" + bean + R"(", "voxel_size": 0.02},
                     "grid": {"cells_per_edge": 6, "wall_cells": 4, "core_size": 0.4}})");
    }
    return cache.at(name);
}

// The report of a grid measured in parts (blocks or parts of blocks, merged or added apart)
// is the whole grid's: its extremes, counts and worst cell exactly, its means (sums in
// another order) to rounding.
void expect_the_whole_report(const GridReport& got, const GridReport& whole) {
    EXPECT_EQ(got.quality.cells, whole.quality.cells);
    EXPECT_EQ(got.quality.inverted_corner_tets, whole.quality.inverted_corner_tets);
    EXPECT_EQ(got.quality.min_scaled_jacobian, whole.quality.min_scaled_jacobian);
    EXPECT_NEAR(got.quality.mean_scaled_jacobian, whole.quality.mean_scaled_jacobian, 1e-12);
    EXPECT_EQ(got.quality.max_non_orthogonality_deg, whole.quality.max_non_orthogonality_deg);
    EXPECT_EQ(got.quality.max_skewness, whole.quality.max_skewness);
    EXPECT_EQ(got.quality.worst_cell, whole.quality.worst_cell);
    ASSERT_TRUE(got.worst_cell && whole.worst_cell);
    EXPECT_EQ(got.worst_cell->block, whole.worst_cell->block);
    EXPECT_EQ(got.worst_cell->k, whole.worst_cell->k);
    ASSERT_TRUE(got.wall && whole.wall);
    EXPECT_EQ(got.wall->wall_cells, whole.wall->wall_cells);
    EXPECT_NEAR(got.wall->first_layer_mean, whole.wall->first_layer_mean, 1e-12);
    EXPECT_EQ(got.wall->orthogonality_max_deg, whole.wall->orthogonality_max_deg);
    EXPECT_NEAR(got.wall->orthogonality_mean_deg, whole.wall->orthogonality_mean_deg, 1e-9);
    EXPECT_EQ(got.wall->growth_ratios, whole.wall->growth_ratios);
    EXPECT_NEAR(got.wall->growth_ratio_mean, whole.wall->growth_ratio_mean, 1e-12);
    EXPECT_EQ(got.wall->growth_ratio_histogram.counts, whole.wall->growth_ratio_histogram.counts);
    // max |u| over h, the mean wall edge: a sum too.
    ASSERT_TRUE(got.max_surface_distance && whole.max_surface_distance);
    EXPECT_NEAR(*got.max_surface_distance, *whole.max_surface_distance,
                1e-9 * *whole.max_surface_distance);
}

class RefineFamily : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(RefineFamily, HasThreeLevelsOfEightTimesTheCells) {
    const Family& f = family(GetParam());
    ASSERT_EQ(f.levels.size(), 3u);
    EXPECT_EQ(f.levels[1].num_cells(), 8 * f.levels[0].num_cells());
    EXPECT_EQ(f.levels[2].num_cells(), 64 * f.levels[0].num_cells());
}

TEST_P(RefineFamily, IsNestedNodeByNode) {
    const Family& f = family(GetParam());
    for (size_t l = 0; l + 1 < f.levels.size(); ++l)
        for (size_t v = 0; v < f.levels[l].points.size(); ++v)
            ASSERT_EQ(f.levels[l + 1].points[v], f.levels[l].points[v]) << "level " << l + 1;
}

TEST_P(RefineFamily, WallNodesLieOnTheBody) {
    const Family& f = family(GetParam());
    for (const GridReport& r : f.reports) {
        ASSERT_TRUE(r.max_surface_distance);
        EXPECT_LT(*r.max_surface_distance, 1e-3);  // max |u| / h over the wall nodes
    }
}

TEST_P(RefineFamily, NoLevelHasAnInvertedCell) {
    for (const GridReport& r : family(GetParam()).reports)
        EXPECT_EQ(r.quality.inverted_corner_tets, 0);
}

TEST_P(RefineFamily, MinScaledJacobianDropsByAtMostFiveHundredthsPerLevel) {
    const Family& f = family(GetParam());
    for (size_t l = 0; l + 1 < f.reports.size(); ++l) {
        std::cout << GetParam() << " level " << l + 1 << " min SJ "
                  << f.reports[l].quality.min_scaled_jacobian << ", level " << l + 2 << " "
                  << f.reports[l + 1].quality.min_scaled_jacobian << "\n";
        EXPECT_GE(f.reports[l + 1].quality.min_scaled_jacobian,
                  f.reports[l].quality.min_scaled_jacobian - 0.05);
    }
}

TEST_P(RefineFamily, FirstLayerAboutHalvesPerLevel) {
    const Family& f = family(GetParam());
    for (size_t l = 0; l + 1 < f.reports.size(); ++l) {
        ASSERT_TRUE(f.reports[l].wall && f.reports[l + 1].wall);
        EXPECT_NEAR(f.reports[l + 1].wall->first_layer_mean / f.reports[l].wall->first_layer_mean,
                    0.5, 0.06);
    }
}

// The level `hexmesh refine` makes block by block, measured as its blocks come and dropped:
// the blocks are those of the assembled level, and so is the report.
TEST_P(RefineFamily, BlockByBlockLevelMatchesTheAssembledOne) {
    const Family& f = family(GetParam());
    const BlockGrid& assembled = f.levels[2];
    GridMeter meter(*f.body);
    size_t b = 0;
    const RefinementStats stats = refine_blocks(f.levels[1], *f.body, {}, [&](RefinedBlock& piece) {
        ASSERT_LT(b, assembled.blocks.size());
        EXPECT_EQ(piece.ids, assembled.blocks[b].node_ids);
        for (size_t m = 0; m < piece.ids.size(); ++m)
            ASSERT_EQ(piece.grid.points[m], assembled.points[piece.ids[m]]) << "block " << b;
        meter.add(piece.grid, piece.grid.blocks[0], &piece.ids);
        ++b;
    });
    EXPECT_EQ(b, assembled.blocks.size());
    EXPECT_EQ(stats.points, Id(assembled.points.size()));
    EXPECT_GT(stats.projected, 0);
    EXPECT_GT(stats.polished, 0);
    const GridReport streamed = meter.report(), whole = f.reports[2];
    EXPECT_EQ(streamed.quality.inverted_corner_tets, 0);
    expect_the_whole_report(streamed, whole);
    // One process adding the blocks in order: the sums too run in the same order.
    EXPECT_EQ(streamed.quality.mean_scaled_jacobian, whole.quality.mean_scaled_jacobian);
    ASSERT_TRUE(streamed.wall && whole.wall);
    EXPECT_EQ(streamed.wall->first_layer_mean, whole.wall->first_layer_mean);
    EXPECT_EQ(*streamed.max_surface_distance, *whole.max_surface_distance);
}

// One process of several makes its share of the blocks and skips the others (their faces
// only): what it makes is the whole refinement's blocks, bit for bit, whichever it makes.
TEST_P(RefineFamily, BlocksMadeWhileTheOthersAreSkippedAreTheSameBitForBit) {
    const Family& f = family(GetParam());
    const BlockGrid& assembled = f.levels[2];
    const size_t blocks = assembled.blocks.size();
    ASSERT_GE(blocks, 3u);
    for (int share = 0; share < 3; ++share) {
        // Every other block, the last alone, all but the first.
        std::vector<bool> made(blocks);
        for (size_t b = 0; b < blocks; ++b)
            made[b] = share == 0 ? b % 2 == 1 : share == 1 ? b + 1 == blocks : b > 0;
        std::vector<size_t> got;
        size_t next = 0;
        const RefinementStats stats = refine_blocks(
            f.levels[1], *f.body, {},
            [&](RefinedBlock& piece) {
                while (next < blocks && !made[next]) ++next;
                ASSERT_LT(next, blocks);
                const Block& block = assembled.blocks[next];
                EXPECT_EQ(piece.grid.blocks[0].name, block.name);
                ASSERT_EQ(piece.ids, block.node_ids) << "block " << next;
                for (size_t m = 0; m < piece.ids.size(); ++m)
                    ASSERT_EQ(piece.grid.points[m], assembled.points[piece.ids[m]])
                        << "share " << share << ", block " << next << ", node " << m;
                got.push_back(next++);
            },
            &made);
        EXPECT_EQ(got.size(), size_t(std::count(made.begin(), made.end(), true)));
        EXPECT_EQ(stats.points, Id(assembled.points.size()));
    }
}

// Processes that each measure some blocks of a grid, then merge their meters at one: the
// report of the whole grid, but for the rounding of its means.
TEST_P(RefineFamily, MetersOfSomeBlocksEachMergedGiveTheWholeReport) {
    const Family& f = family(GetParam());
    const BlockGrid& grid = f.levels[2];
    GridMeter first(*f.body), second(*f.body);
    Id cell = 0;
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        (b % 2 ? second : first)
            .add(grid, grid.blocks[b], nullptr, CellNumbering{cell, {0, 0, 0}, {}});
        cell += grid.blocks[b].cells().count();
    }
    first.merge(second.pack());
    expect_the_whole_report(first.report(), f.reports[2]);
}

// Blocks cut in two along i (parallel to the wall) and measured part by part, as processes
// that share a block do: the lines on the cut count once, the report is the whole one.
TEST_P(RefineFamily, BlocksMeasuredInTwoPartsGiveTheWholeReport) {
    const Family& f = family(GetParam());
    GridMeter meter(*f.body);
    Id first = 0;
    refine_blocks(f.levels[1], *f.body, {}, [&](RefinedBlock& piece) {
        const Dims cells = piece.grid.blocks[0].cells();
        const int cut = cells.ni / 2;
        for (const auto& [lo, hi] : {std::pair{0, cut}, std::pair{cut, cells.ni}}) {
            const RefinedBlock part = part_of(piece, 0, lo, hi);
            meter.add(part.grid, part.grid.blocks[0], &part.ids,
                      CellNumbering{first, {lo, 0, 0}, cells});
        }
        first += cells.count();
    });
    expect_the_whole_report(meter.report(), f.reports[2]);
}

// The report page's pictures drawn by two processes, each some blocks in order, then merged:
// the pictures one process draws, pixel for pixel.
TEST_P(RefineFamily, PicturesDrawnApartAndMergedAreThePicturesDrawnWhole) {
    const BlockGrid& grid = family(GetParam()).levels[2];
    GridPictures whole = grid_pictures_for(grid), first = grid_pictures_for(grid),
                 second = grid_pictures_for(grid);
    std::vector<double> values;
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        const Block& block = grid.blocks[b];
        values.resize(size_t(block.cells().count()));
        scaled_jacobians(grid, block, values.data());
        whole.add_block(grid, block, values.data());
        GridPictures& part = b % 2 ? second : first;
        part.set_order(std::uint32_t(b));
        part.add_block(grid, block, values.data());
    }
    first.merge(second.pack());
    const std::vector<Picture> a = whole.pictures(), merged = first.pictures();
    ASSERT_EQ(a.size(), merged.size());
    for (size_t n = 0; n < a.size(); ++n) EXPECT_TRUE(a[n].png == merged[n].png) << a[n].title;
}

// Shares for processes: whole blocks balanced while there are enough, then halves of the
// largest pieces, never across a wall-normal line; parts of a fine block join back into it.
TEST_P(RefineFamily, BlocksAreSharedWholeThenSplitAlongLinesParallelToTheWall) {
    const Family& f = family(GetParam());
    const BlockGrid& coarse = f.levels[1];
    const size_t blocks = coarse.blocks.size();
    const Id cells = 8 * coarse.num_cells();
    Id largest = 0;
    for (const Block& b : coarse.blocks) largest = std::max(largest, 8 * b.cells().count());
    for (int processes : {1, 2, 3, int(blocks), int(blocks) + 2, 4 * int(blocks)}) {
        const std::vector<BlockPiece> pieces = share_blocks(coarse, processes);
        std::vector<Id> load(size_t(processes), 0);
        Id total = 0;
        for (const BlockPiece& p : pieces) {
            ASSERT_LT(p.process, processes);
            load[size_t(p.process)] += p.cells;
            total += p.cells;
            const Block& block = coarse.blocks[p.block];
            EXPECT_FALSE(block.face_patch[size_t(2 * p.axis)] == "wall" ||
                         block.face_patch[size_t(2 * p.axis + 1)] == "wall")
                << "block " << block.name << " split along its wall-normal lines";
        }
        EXPECT_EQ(total, cells);
        const auto [low, high] = std::minmax_element(load.begin(), load.end());
        if (size_t(processes) <= blocks) {
            EXPECT_EQ(pieces.size(), blocks) << processes;
            EXPECT_LE(*high - *low, largest) << processes;
        } else {
            EXPECT_EQ(pieces.size(), size_t(processes));
            EXPECT_GT(*low, 0) << processes << " processes: one has nothing to make";
        }
    }
    // A fine block cut in three along j, joined again.
    BlockRefiner refiner(coarse);
    const RefinedBlock fine = refiner.refine(0);
    const int nj = fine.grid.blocks[0].cells().nj;
    const std::vector<RefinedBlock> parts = {part_of(fine, 1, 0, 3), part_of(fine, 1, 3, 7),
                                             part_of(fine, 1, 7, nj)};
    EXPECT_EQ(parts[1].grid.blocks[0].cells().nj, 4);
    EXPECT_TRUE(parts[1].grid.blocks[0].face_patch[2].empty());
    EXPECT_TRUE(parts[1].shared[0]);  // on the cut
    const RefinedBlock joined = join_parts(parts, 1);
    EXPECT_EQ(joined.ids, fine.ids);
    EXPECT_EQ(joined.grid.points, fine.grid.points);
    EXPECT_EQ(joined.grid.blocks[0].face_patch, fine.grid.blocks[0].face_patch);
}

INSTANTIATE_TEST_SUITE_P(Bodies, RefineFamily, ::testing::Values("sphere", "bean"));

TEST(RefinedWallLayers, SplitTheFirstCellInTwoOfRatioSqrtR) {
    const WallLayers fine = refined_wall_layers({0.01, 1.21, 4}, 2);
    EXPECT_NEAR(fine.growth_ratio, 1.1, 1e-12);
    EXPECT_NEAR(fine.first_height * (1 + 1.1), 0.01, 1e-15);  // h1 + h1 sqrt(r) = h
    EXPECT_EQ(fine.layers, 8);
    const WallLayers finer = refined_wall_layers({0.01, 1.21, 4}, 3);
    EXPECT_NEAR(finer.first_height * (1 + std::sqrt(1.1)), fine.first_height, 1e-15);
    EXPECT_EQ(finer.layers, 16);
}

// The family `run` makes of a bundled case (cases/NAME/case.json) with 3 levels: along every
// wall-normal line, within the refined law's layers, the spacing grows (ratio >= 1) and
// 95 % of the growth ratios are within 5 % of the refined ratio, r^(1/2) at level 2 and
// r^(1/4) at level 3 (refined_wall_layers). Measured before the split followed that law
// (cubic stencils in the index across the end of the layers): sphere 0.992 at level 2 and
// 81.8 % within, box with cylinder 0.208 and 77.6 %.
class RefinedLaw : public ::testing::TestWithParam<std::string> {};

TEST_P(RefinedLaw, LevelsTwoAndThreeFollowTheRefinedGrowthRatio) {
    Case c = read_case(std::string(HEXMESH_SOURCE_DIR) + "/cases/" + GetParam() + "/case.json");
    c.refinement.levels = 3;
    c.outputs = {"vtk"};
    const std::filesystem::path dir = test::remove_at_exit(
        std::filesystem::temp_directory_path() / ("hexmesh_test_refined_law_" + GetParam()));
    std::filesystem::remove_all(dir);
    RunOptions options;
    options.keep_invalid = true;  // measured whatever else the levels do
    std::ostringstream log;
    const RunResult run = run_case(c, dir.string(), options, log);
    ASSERT_EQ(run.level_reports.size(), 3u);
    const WallLayers law = wall_layers(c);
    for (int level = 2; level <= 3; ++level) {
        const GridReport& r = run.level_reports[level - 1];
        ASSERT_TRUE(r.wall);
        const WallQuality& w = *r.wall;
        std::cout << GetParam() << " level " << level << ": growth ratio " << w.growth_ratio_min
                  << " .. " << w.growth_ratio_max << ", " << 100 * w.growth_ratio_within_5_percent
                  << " % within 5 % of " << w.growth_ratio_target << "; first layer "
                  << 100 * w.first_layer_within_10_percent << " % within 10 %; min SJ "
                  << r.quality.min_scaled_jacobian << "\n";
        EXPECT_NEAR(w.growth_ratio_target, std::pow(law.growth_ratio, std::pow(0.5, level - 1)),
                    1e-12);
        EXPECT_GE(w.growth_ratio_min, 1.0) << "level " << level;
        EXPECT_GE(w.growth_ratio_within_5_percent, 0.95) << "level " << level;
        EXPECT_EQ(w.first_layer_within_10_percent, 1.0) << "level " << level;
        EXPECT_EQ(r.quality.inverted_cells, 0) << "level " << level;
    }
}

INSTANTIATE_TEST_SUITE_P(Cases, RefinedLaw, ::testing::Values("sphere", "box_cylinder"));

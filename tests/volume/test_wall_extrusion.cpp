#include <gtest/gtest.h>

#include <cmath>

#include "surface/analytic.h"
#include "volume/feature_snapping.h"
#include "volume/o_h_grid.h"
#include "volume/single_block_grid.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

using namespace hexmesh;

namespace {

// The O-H grid of a box body, 8 cells per patch edge, 6 from the core to the wall.
BlockGrid box_grid(const Box& body, double core_size) {
    OHGridOptions o;
    o.cells_per_edge = 8;
    o.wall_cells = 6;
    o.core_size = core_size;
    return make_o_h_grid(body, o);
}

}  // namespace

// On a box the layer nodes of every line, at its faces, edges and corners alike, end up at
// the law's distance from every face through their wall node: value = -d_m exactly.
TEST(WallExtrusion, LayersLieOnTheOffsetsOfEveryFaceAtEdgesAndCorners) {
    const Box body(Vec3::Zero(), Vec3(1, 0.75, 0.5));
    BlockGrid grid = box_grid(body, 0.4);
    const FeatureSnapping snapped = snap_to_features(grid, body);
    ASSERT_EQ(snapped.corner_nodes, 8);
    ASSERT_EQ(snapped.crease_nodes, 12 * 7);

    const WallLayers law{0.01, 1.2, 3};
    const std::vector<bool> placed = extrude_wall_layers(grid, body, law);
    const double d[4] = {0, 0.01, 0.022, 0.0364};
    Id lines = 0, crease_lines = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p, ++lines) {
                crease_lines += grid.kinds[f.node(p, q, 0)] != VertexKind::slip;
                for (int m = 0; m <= 3; ++m) {
                    const Id v = f.node(p, q, m);
                    EXPECT_TRUE(placed[v]);
                    EXPECT_NEAR(body.value(grid.points[v]), -d[m], 1e-12)
                        << p << " " << q << " " << m;
                }
            }
    EXPECT_GT(crease_lines, 0);
    EXPECT_EQ(lines, 6 * 9 * 9);
}

// Where the body is thin a line takes only the layers that fit it (layers_that_fit of its
// length), each at the law's distance from its wall node; thin_wall_lines counts those lines and
// names the one cut the most.
TEST(WallExtrusion, ThinPartsOfTheBodyTakeFewerLayers) {
    const Box body(Vec3::Zero(), Vec3(1, 0.75, 0.25));
    BlockGrid grid = box_grid(body, 0.2);
    snap_to_features(grid, body);
    const WallLayers law{0.04, 1.5, 4};  // 0.325 thick
    const ThinWallLines thin = thin_wall_lines(grid, law);
    EXPECT_EQ(thin.lines, 6 * 9 * 9);
    ASSERT_GT(thin.cut, 0);
    EXPECT_LT(thin.cut, thin.lines);
    EXPECT_GE(thin.fewest, 1);
    EXPECT_LT(thin.fewest, 4);
    EXPECT_LT(thin.length, 0.325);
    EXPECT_NEAR(std::abs(thin.wall.z()), 0.25, 1e-12);  // on a face of the thin side

    std::vector<int> fit;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p)
                fit.push_back(layers_that_fit(line_length(grid, f, p, q), f.depth - 1, law));
    const std::vector<bool> placed = extrude_wall_layers(grid, body, law);
    const double d[5] = {0, 0.04, 0.1, 0.19, 0.325};
    size_t line = 0;
    Id cut = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p, ++line) {
                cut += fit[line] < 4;
                const Vec3 x0 = grid.points[f.node(p, q, 0)];
                const bool on_a_face = grid.kinds[f.node(p, q, 0)] == VertexKind::slip;
                for (int m = 0; m <= fit[line]; ++m) {
                    EXPECT_TRUE(placed[f.node(p, q, m)]);
                    if (on_a_face)  // straight along the face's normal
                        EXPECT_NEAR((grid.points[f.node(p, q, m)] - x0).norm(), d[m], 1e-12);
                }
                if (fit[line] < 4) EXPECT_FALSE(placed[f.node(p, q, fit[line] + 1)]);
            }
    EXPECT_EQ(cut, thin.cut);
}

// In a single block walled on all six sides every wall-normal line runs into lines from the
// opposite and the neighbouring faces: none is laid, the layers stay as the block was built.
TEST(WallExtrusion, CrossingLinesOfASingleBlockAreLeftAsBuilt) {
    const Box body(Vec3::Zero(), Vec3(1, 0.75, 0.5));
    SingleBlockOptions o;
    o.cells = {8, 6, 6};
    o.wall_layers = {0.02, 1.2, 2};
    BlockGrid grid = make_single_block_grid(body, o);
    const std::vector<Vec3> built = grid.points;
    const std::vector<bool> placed = extrude_wall_layers(grid, body, o.wall_layers);
    EXPECT_EQ(std::count(placed.begin(), placed.end(), true), 0);
    EXPECT_EQ(grid.points, built);
}

// With blend = B the nodes beyond the layers follow them over B nodes only: nodes
// layers + 1 .. layers + B move (by less and less), the rest of each line stays put.
TEST(WallExtrusion, BlendLimitsTheShiftedNodesBeyondTheLayers) {
    const Ellipsoid body(Vec3::Zero(), Vec3(1.0, 0.8, 0.6));
    OHGridOptions o;
    o.cells_per_edge = 8;
    o.wall_cells = 12;
    BlockGrid grid = make_o_h_grid(body, o);
    const std::vector<Vec3> built = grid.points;
    const WallLayers law{0.01, 1.2, 3};
    const int blend = 4;
    extrude_wall_layers(grid, body, law, blend);
    Id moved_beyond = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                double previous = (grid.points[f.node(p, q, 3)] - built[f.node(p, q, 3)]).norm();
                for (int m = 4; m < f.depth; ++m) {
                    const double move =
                        (grid.points[f.node(p, q, m)] - built[f.node(p, q, m)]).norm();
                    if (m > 3 + blend) {
                        EXPECT_EQ(move, 0.0) << p << " " << q << " " << m;
                    } else {
                        EXPECT_LE(move, previous + 1e-15);
                        moved_beyond += move > 0;
                    }
                    previous = move;
                }
            }
    EXPECT_GT(moved_beyond, 0);
}

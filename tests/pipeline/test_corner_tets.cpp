#include <gtest/gtest.h>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "surface/analytic.h"
#include "untangle/untangle.h"
#include "volume/o_h_grid.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// A 4 x 4 x 4 block of unit cells, its outer nodes fixed, whose second layer of nodes (k = 1)
// lies on the first (k = 0) over the inner 3 x 3 nodes: the cells between are flat along k,
// as where a line's nodes are laid on top of each other.
BlockGrid flattened_block() {
    BlockGrid grid;
    Block block{"block", {5, 5, 5}, {}, {}};
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                const bool inner = i > 0 && j > 0 && k > 0 && i < 4 && j < 4 && k < 4;
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.push_back(Vec3(i, j, k == 1 && inner ? 0.0 : double(k)));
                grid.kinds.push_back(inner ? VertexKind::interior : VertexKind::fixed);
            }
    grid.blocks.push_back(block);
    return grid;
}

}  // namespace

// A cell flat along an axis takes there the shortest of its other mean edge lengths as its
// target, and the untangling lifts the layer (with targets of no volume it leaves the 72
// corner tets inverted; on an exterior grid whose lines' nodes lay on top of each other beside
// a sharp tip, the energy was NaN and the untangling stopped without a step).
TEST(CornerTets, AFlatCellGetsATargetWithVolume) {
    BlockGrid grid = flattened_block();
    const Sphere body(Vec3(2, 2, 2), 10);  // no node slides on it
    GridProblem g = corner_tet_problem(grid, grid.points, body, {}, {});
    untangle::Problem& p = g.problem;
    for (const Vec3& edges : p.hex_edges) EXPECT_GT(edges.minCoeff(), 0.0) << edges.transpose();
    untangle::UntangleOptions o;
    const untangle::UntangleResult r = untangle::untangle_and_optimize(p, o);
    EXPECT_GT(r.inverted_before, 0);
    EXPECT_EQ(r.inverted_after, 0) << r.stopped;
}

// Every wall quad of an O-H grid is held (6 faces of 8 x 8), and the untangling lets them go
// when it cannot repair the wall with them: two rows of wall nodes near the tip of a long
// ellipsoid crossed (16 inverted corner tets); held with weight 100 they untangle as they
// are; with 1e6 the quads' gaps outweigh the folds, the untangling stalls, the quads are let
// go and it untangles without them.
TEST(CornerTets, WallQuadsHeldTooHardToUntangleAreLetGo) {
    const Ellipsoid body(Vec3::Zero(), Vec3(3.0, 0.4, 0.4));
    for (const double fidelity : {100.0, 1e6}) {
        OHGridOptions o;
        o.cells_per_edge = 8;
        o.wall_cells = 4;
        BlockGrid grid = make_o_h_grid(body, o);
        const WallFace f = wall_faces(grid)[0];
        for (int k = 2; k < 6; ++k)
            std::swap(grid.points[f.node(k, 4, 0)], grid.points[f.node(k + 1, 3, 0)]);
        GridProblem g = corner_tet_problem(grid, grid.points, body, {}, {});
        hold_wall_quads(grid, grid.points, body, fidelity, g);
        ASSERT_EQ(g.problem.held_quads.size(), 6u * 8 * 8);
        const untangle::UntangleResult r =
            untangle::untangle_and_optimize(g.problem, untangle::UntangleOptions{});
        EXPECT_EQ(r.inverted_before, 16);
        EXPECT_EQ(r.inverted_after, 0) << fidelity << ": " << r.stopped;
        EXPECT_EQ(r.wall_let_go, fidelity > 1000) << fidelity;
        EXPECT_EQ(g.problem.held_quads.empty(), fidelity > 1000) << fidelity;
    }
    // Weight 0 holds nothing.
    BlockGrid grid = make_o_h_grid(body, OHGridOptions{});
    GridProblem g = corner_tet_problem(grid, grid.points, body, {}, {});
    hold_wall_quads(grid, grid.points, body, 0, g);
    EXPECT_TRUE(g.problem.held_quads.empty());
    EXPECT_FALSE(g.problem.surface_value);
}

}  // namespace hexmesh

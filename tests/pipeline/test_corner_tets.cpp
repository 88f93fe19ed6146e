#include <gtest/gtest.h>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "surface/analytic.h"
#include "untangle/untangle.h"

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

}  // namespace hexmesh

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/pipeline/mend_cells.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/analytic.h"
#include "tests/hand_grids.h"
#include "volume/o_grid.h"

namespace hexmesh {
namespace {

// A 4 x 4 x 4 block of unit cells whose 27 inner nodes are each moved up to `amplitude` along
// each axis; the outer nodes fixed.
BlockGrid jittered_block(unsigned seed, double amplitude) {
    BlockGrid grid;
    Block block{"block", {5, 5, 5}, {}, {}};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-amplitude, amplitude);
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                const bool inner = i > 0 && j > 0 && k > 0 && i < 4 && j < 4 && k < 4;
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.push_back(
                    Vec3(i, j, k) +
                    (inner ? Vec3(jitter(rng), jitter(rng), jitter(rng)) : Vec3::Zero()));
                grid.kinds.push_back(inner ? VertexKind::interior : VertexKind::fixed);
            }
    grid.blocks.push_back(block);
    return grid;
}

// A node of a test block: where it is, its kind, and whether it keeps its level of u.
struct PlacedNode {
    Vec3 x;
    VertexKind kind;
    bool on_level = false;
};

// One block of ni x nj x nk nodes (i fastest), node (i, j, k) as place(i, j, k) gives it; the
// nodes' on_level flags into `on_level`.
template <class Place>
BlockGrid placed_block(int ni, int nj, int nk, Place place, std::vector<bool>& on_level) {
    BlockGrid grid;
    Block block{"block", {ni, nj, nk}, {}, {}};
    on_level.clear();
    for (int k = 0; k < nk; ++k)
        for (int j = 0; j < nj; ++j)
            for (int i = 0; i < ni; ++i) {
                const PlacedNode n = place(i, j, k);
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.push_back(n.x);
                grid.kinds.push_back(n.kind);
                on_level.push_back(n.on_level);
            }
    grid.blocks.push_back(block);
    return grid;
}

// The kind of a node of a wall and its layers: fixed unless `moving`, slip at the wall (k = 0),
// interior above it.
VertexKind layer_kind(bool moving, int k) {
    return !moving ? VertexKind::fixed : k == 0 ? VertexKind::slip : VertexKind::interior;
}

// Grids with cells the solver refuses (face pyramids, inverted corner tets): the mend never
// lowers the smallest margin around them, never moves a fixed node, and leaves none refused
// (39 grids of 40, 144 refused cells).
TEST(MendRefusedCells, RefusedCellsOfJitteredBlocksAreMended) {
    const Sphere body(Vec3(2, 2, 2), 10);  // unused: no node slides
    int grids = 0, mended = 0;
    Id before = 0, after = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        BlockGrid grid = jittered_block(seed, 0.42);
        const MendResult r = mend_refused_cells(grid, body);
        EXPECT_EQ(r.refused_before,
                  Id(find_refused_cells(to_hex_mesh(jittered_block(seed, 0.42))).size()));
        EXPECT_EQ(r.refused_after, Id(find_refused_cells(to_hex_mesh(grid)).size()));
        if (r.refused_before == 0) continue;
        ++grids;
        before += r.refused_before;
        after += r.refused_after;
        mended += r.refused_after == 0;
        EXPECT_LE(r.refused_after, r.refused_before) << "seed " << seed;
        EXPECT_GE(r.min_margin_after, r.min_margin_before) << "seed " << seed;
        const BlockGrid start = jittered_block(seed, 0.42);
        for (size_t v = 0; v < grid.points.size(); ++v) {
            if (grid.kinds[v] == VertexKind::fixed) {
                EXPECT_EQ(grid.points[v], start.points[v]);
            }
        }
    }
    EXPECT_GE(grids, 10);
    EXPECT_EQ(mended, grids) << before << " refused cells before, " << after << " after";
}

// Jittered blocks with inverted cells (an inverted corner tet, exact orientation; 1102 in 40
// grids): the mend never leaves a grid more of them than it found, whatever it does to the
// cells a solver refuses otherwise, and leaves under 2 % of them (6; 91 when a move could trade
// a valid cell for fewer refused ones); the lift after it never raises their count and never
// lowers the worst scaled Jacobian.
TEST(MendRefusedCells, InvertedCellsAreUntangledFirst) {
    const Sphere body(Vec3(2, 2, 2), 10);  // unused: no node slides
    Id before = 0, after = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        BlockGrid grid = jittered_block(seed, 0.8);
        const Id inverted = count_inversions(to_hex_mesh(grid)).cells;
        before += inverted;
        mend_refused_cells(grid, body);
        const Id mended = count_inversions(to_hex_mesh(grid)).cells;
        EXPECT_LE(mended, inverted) << "seed " << seed;
        const double worst = measure_quality(to_hex_mesh(grid)).min_scaled_jacobian;
        const LiftResult r = lift_worst_cells(grid, body);
        const Id lifted = count_inversions(to_hex_mesh(grid)).cells;
        EXPECT_LE(lifted, mended) << "seed " << seed;
        EXPECT_GE(r.min_sj_after, worst) << "seed " << seed;
        after += lifted;
    }
    EXPECT_GT(before, 1000);
    EXPECT_LT(50 * after, before) << after << " inverted cells left of " << before;
}

// Two cells whose shared face and end faces are skewed past checkMesh's limit (5), every corner
// positive: the four nodes of the shared face, free, are moved until no face is over 4; the
// others stay.
TEST(MendRefusedCells, FacesOfSkewnessOverFourAreMended) {
    const Sphere body(Vec3(0, 0, 0), 10);  // unused: no node slides
    BlockGrid grid = test::leaning_cells(2.0);
    for (Id v = 4; v < 8; ++v) grid.kinds[v] = VertexKind::interior;  // the layer k = 1
    const MendResult r = mend_refused_cells(grid, body);
    EXPECT_EQ(r.refused_before, 2);
    EXPECT_EQ(r.refused_after, 0);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.highly_skewed_faces, 0);
    EXPECT_LE(q.max_skewness, max_solver_skewness);
    EXPECT_TRUE(q.solver_valid());
    const BlockGrid start = test::leaning_cells(2.0);
    for (Id v : {0, 1, 2, 3, 8, 9, 10, 11}) EXPECT_EQ(grid.points[v], start.points[v]);
}

// Jittered blocks a solver accepts (the mend's, at a smaller amplitude), every cell under 0.9
// lifted: the lift raises the worst scaled Jacobian of each by more than 0.05, never moves a
// fixed node and leaves no cell a solver refuses.
TEST(LiftWorstCells, TheWorstCellOfJitteredBlocksIsRaised) {
    const Sphere body(Vec3(2, 2, 2), 10);  // unused: no node slides
    int grids = 0;
    for (unsigned seed = 1; seed <= 20; ++seed) {
        BlockGrid grid = jittered_block(seed, 0.3);
        const QualityReport before = measure_quality(to_hex_mesh(grid));
        if (!before.solver_valid()) continue;
        ++grids;
        LiftOptions o;
        o.below = 0.9;  // every cell of the block
        const LiftResult r = lift_worst_cells(grid, body, o);
        EXPECT_EQ(r.min_sj_before, before.min_scaled_jacobian) << "seed " << seed;
        const QualityReport after = measure_quality(to_hex_mesh(grid));
        EXPECT_EQ(r.min_sj_after, after.min_scaled_jacobian) << "seed " << seed;
        EXPECT_GT(after.min_scaled_jacobian, before.min_scaled_jacobian + 0.05) << "seed " << seed;
        EXPECT_TRUE(after.solver_valid()) << "seed " << seed;
        EXPECT_GT(r.moves, 0);
        const BlockGrid start = jittered_block(seed, 0.3);
        for (size_t v = 0; v < grid.points.size(); ++v)
            if (grid.kinds[v] == VertexKind::fixed) {
                EXPECT_EQ(grid.points[v], start.points[v]);
            }
    }
    EXPECT_GE(grids, 10);
}

// Jittered blocks with every cell lifted (their best is the undisturbed lattice, 1), with and
// without the max-min ascent: node by node, each node ends at a max-min point of its own cells
// (0.92 on average over 36 blocks); the worst cells' nodes moved together then raise every
// block over 0.98.
TEST(LiftWorstCells, TheWorstCellsNodesMovedTogetherReachTheLatticesBest) {
    const Sphere body(Vec3(2, 2, 2), 10);  // unused: no node slides
    int grids = 0;
    double by_nodes = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        BlockGrid alone = jittered_block(seed, 0.3), together = alone;
        if (!measure_quality(to_hex_mesh(alone)).solver_valid()) continue;
        ++grids;
        LiftOptions o;
        o.below = 1.01;  // every cell
        o.ascent = false;
        const LiftResult a = lift_worst_cells(alone, body, o);
        by_nodes += a.min_sj_after;
        EXPECT_EQ(a.joint_steps, 0);
        o.ascent = true;
        const LiftResult r = lift_worst_cells(together, body, o);
        EXPECT_GT(r.min_sj_after, 0.98) << "seed " << seed;
        EXPECT_GT(r.joint_steps, 0) << "seed " << seed;
        EXPECT_TRUE(measure_quality(to_hex_mesh(together)).solver_valid()) << "seed " << seed;
        const BlockGrid start = jittered_block(seed, 0.3);
        for (size_t v = 0; v < together.points.size(); ++v)
            if (together.kinds[v] == VertexKind::fixed) {
                EXPECT_EQ(together.points[v], start.points[v]);
            }
    }
    EXPECT_GE(grids, 30);
    EXPECT_LT(by_nodes / grids, 0.95);
}

// A wall on the plane z = 0 (the top of a large box) under a 4 x 4 x 3 block of unit cells whose
// wall nodes (slip) and two layers above them (on_level) are pushed sideways: the lift raises
// the worst scaled Jacobian with every wall node still on z = 0 and every layer node at its own
// height.
TEST(LiftWorstCells, WallNodesSlideAndLayerNodesKeepTheirHeights) {
    const Box body(Vec3(0, 0, -50), Vec3(50, 50, 50));  // u = z above its top face
    std::vector<bool> on_level;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> shift(-0.3, 0.3);
    BlockGrid grid = placed_block(
        5, 5, 4,
        [&](int i, int j, int k) {
            const bool inner = i > 0 && j > 0 && i < 4 && j < 4 && k < 3;
            return PlacedNode{
                Vec3(i, j, k) + (inner ? Vec3(shift(rng), shift(rng), 0) : Vec3::Zero()),
                layer_kind(inner, k), inner && k > 0};
        },
        on_level);
    const BlockGrid start = grid;
    LiftOptions o;
    o.on_level = on_level;
    o.below = 0.9;
    const LiftResult r = lift_worst_cells(grid, body, o);
    EXPECT_GT(r.min_sj_after, r.min_sj_before + 0.05);
    EXPECT_GT(r.moves, 0);
    int moved = 0;
    for (size_t v = 0; v < grid.points.size(); ++v) {
        EXPECT_NEAR(grid.points[v].z(), start.points[v].z(), 1e-9) << "node " << v;
        moved += grid.points[v] != start.points[v];
        if (grid.kinds[v] == VertexKind::fixed) {
            EXPECT_EQ(grid.points[v], start.points[v]);
        }
    }
    EXPECT_GT(moved, 10);
    EXPECT_TRUE(measure_quality(to_hex_mesh(grid)).solver_valid());
}

// The 4 x 4 x 4 unit cells filling a box, their nodes pushed along their free directions (a
// face's node in its face, an edge's along its edge, an inner node anywhere; the box's corners
// stay): the lift raises the worst scaled Jacobian and leaves every node on its face or edge.
TEST(LiftWorstCells, NodesOnTheBoxesEdgesSlideAlongThem) {
    const Box body(Vec3(2, 2, 2), Vec3(2, 2, 2));
    std::vector<bool> on_level;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> shift(-0.3, 0.3);
    BlockGrid grid = placed_block(
        5, 5, 5,
        [&](int i, int j, int k) {
            const std::array<int, 3> ijk = {i, j, k};
            Vec3 x(i, j, k);
            int on = 0;  // coordinates on the box's faces
            for (int a = 0; a < 3; ++a) {
                if (ijk[a] == 0 || ijk[a] == 4)
                    ++on;
                else
                    x[a] += shift(rng);
            }
            return PlacedNode{x, on == 0   ? VertexKind::interior
                                 : on == 1 ? VertexKind::slip
                                 : on == 2 ? VertexKind::feature_edge
                                           : VertexKind::corner};
        },
        on_level);
    const BlockGrid start = grid;
    LiftOptions o;
    o.below = 0.9;
    const LiftResult r = lift_worst_cells(grid, body, o);
    EXPECT_GT(r.min_sj_after, r.min_sj_before + 0.05);
    int edge_moves = 0;
    for (size_t v = 0; v < grid.points.size(); ++v) {
        for (int a = 0; a < 3; ++a) {
            const double s = start.points[v][a];
            if (s == 0 || s == 4) {
                EXPECT_NEAR(grid.points[v][a], s, 1e-9) << "node " << v;
            }
        }
        edge_moves +=
            grid.kinds[v] == VertexKind::feature_edge && grid.points[v] != start.points[v];
    }
    EXPECT_GT(edge_moves, 5);
    EXPECT_TRUE(measure_quality(to_hex_mesh(grid)).solver_valid());
}

// A sector of an O-grid round a cylinder of radius 3 (cells about 0.5 wide, 0.1 high): the wall
// nodes (slip) and the two layers above them (on_level) pushed round the axis and along it. The
// lift raises the worst scaled Jacobian with every wall node still on the cylinder and every
// layer node at its own distance from it, though each move leaves the curved level set first.
TEST(LiftWorstCells, NodesOfACurvedWallAndItsLayersStayOnTheirLevels) {
    const Cylinder body(Vec3(0, 0, 0), 3.0, 100.0);
    std::vector<bool> on_level;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> shift(-0.2, 0.2);
    BlockGrid grid = placed_block(
        6, 6, 5,
        [&](int i, int j, int k) {
            const bool inner = i > 0 && j > 0 && i < 5 && j < 5 && k < 3;
            const double radius = 3.0 + 0.1 * k;
            const double angle = (0.5 * i + (inner ? shift(rng) : 0)) / 3.0;
            const double z = 0.5 * j + (inner ? shift(rng) : 0);
            return PlacedNode{Vec3(radius * std::cos(angle), radius * std::sin(angle), z),
                              layer_kind(inner, k), inner && k > 0};
        },
        on_level);
    const BlockGrid start = grid;
    LiftOptions o;
    o.on_level = on_level;
    o.below = 0.95;
    const LiftResult r = lift_worst_cells(grid, body, o);
    EXPECT_GT(r.min_sj_after, r.min_sj_before + 0.02);
    int moved = 0;
    for (size_t v = 0; v < grid.points.size(); ++v) {
        EXPECT_NEAR(body.value(grid.points[v]), body.value(start.points[v]), 1e-7) << "node " << v;
        moved += grid.points[v] != start.points[v];
    }
    EXPECT_GT(moved, 10);
    EXPECT_TRUE(measure_quality(to_hex_mesh(grid)).solver_valid());
}

// A line leaning over a plane wall (z = 0) in a 4 x 4 x 6 block: its wall node (slip) and three
// layer nodes (on_level, 0.1 apart) lean by 0.3 per layer along x (worst scaled Jacobian 0.24),
// every other node fixed. Lifted with the line also moved whole or sheared, it comes out at
// least as straight as by its nodes alone (0.89), over 0.85, every node still at its height
// (without the worst cells' joint ascent, after which either is 0.99).
TEST(LiftWorstCells, ALeaningLineIsStraightenedWhole) {
    const Box body(Vec3(0, 0, -50), Vec3(50, 50, 50));  // u = z above its top face
    std::vector<bool> on_level;
    BlockGrid grid = placed_block(
        5, 5, 7,
        [&](int i, int j, int k) {
            const bool inner = i == 2 && j == 2 && k < 4;
            const double z = k < 4 ? 0.1 * k : 0.3 + 0.5 * (k - 3);
            return PlacedNode{Vec3(i + (inner ? 0.3 * k : 0), j, z), layer_kind(inner, k),
                              inner && k > 0};
        },
        on_level);
    std::vector<Id> line;
    for (int k = 0; k < 4; ++k) line.push_back(Id(2 + 5 * (2 + 5 * k)));
    const BlockGrid start = grid;
    LiftOptions o;
    o.on_level = on_level;
    o.below = 0.9;
    o.ascent = false;  // what the lines' moves add to the node's own
    BlockGrid alone = grid;
    const LiftResult by_nodes = lift_worst_cells(alone, body, o);
    o.lines = {line};
    const LiftResult r = lift_worst_cells(grid, body, o);
    EXPECT_EQ(by_nodes.line_moves, 0);
    EXPECT_GT(r.line_moves, 0);
    EXPECT_LT(r.min_sj_before, 0.25);
    EXPECT_GT(r.min_sj_after, 0.85);
    EXPECT_GE(r.min_sj_after, by_nodes.min_sj_after);
    for (size_t v = 0; v < grid.points.size(); ++v)
        EXPECT_NEAR(grid.points[v].z(), start.points[v].z(), 1e-9) << "node " << v;
    EXPECT_TRUE(measure_quality(to_hex_mesh(grid)).solver_valid());
}

// The exterior O-grid of the unit sphere with its far-field nodes (on a sphere of radius 4) each
// pushed along the sphere by up to 0.25 of a far cell (worst scaled Jacobian 0.24):
// far_field_sphere finds that sphere and those nodes (and none round a far-field box); with them
// held the lift cannot raise the far layer's cells, which their far quads bound, past 0.35 (0.25);
// with them sliding on it, over 0.8 (0.85), every far node still on the sphere.
TEST(LiftWorstCells, FarFieldNodesSlideOnTheirSphere) {
    const Sphere body(Vec3::Zero(), 1.0);
    OGridOptions og;
    og.cells_per_edge = 6;
    og.layers = 6;
    og.far_field_size = 4;
    BlockGrid grid = make_o_grid(body, og);
    std::vector<bool> on_far;
    const std::optional<Sphere> far = far_field_sphere(grid, on_far);
    ASSERT_TRUE(far.has_value());
    ASSERT_EQ(on_far.size(), grid.points.size());
    EXPECT_EQ(std::count(on_far.begin(), on_far.end(), true), 6 * 6 * 6 + 2);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> push(-0.25, 0.25);
    const double cell = 4 * 1.5707963 / 6;  // a far cell's edge, about
    for (size_t v = 0; v < grid.points.size(); ++v) {
        if (!on_far[v]) continue;
        EXPECT_NEAR(far->value(grid.points[v]), 0, 1e-9);
        EXPECT_NEAR(grid.points[v].norm(), 4, 1e-9);
        const Vec3 x = grid.points[v] + cell * Vec3(push(rng), push(rng), push(rng));
        grid.points[v] = 4 * x.normalized();
    }
    LiftOptions o;
    o.below = 0.9;
    BlockGrid held = grid;
    const LiftResult h = lift_worst_cells(held, body, o);
    o.far = &*far;
    o.on_far = on_far;
    const LiftResult r = lift_worst_cells(grid, body, o);
    EXPECT_LT(r.min_sj_before, 0.3);
    EXPECT_LT(h.min_sj_after, 0.35);
    EXPECT_GT(r.min_sj_after, 0.8);
    int moved = 0;
    for (size_t v = 0; v < grid.points.size(); ++v) {
        if (!on_far[v]) continue;
        EXPECT_NEAR(grid.points[v].norm(), 4, 1e-9) << "node " << v;
        moved += grid.points[v] != held.points[v];
    }
    EXPECT_GT(moved, 10);
    EXPECT_TRUE(measure_quality(to_hex_mesh(grid)).solver_valid());
    og.far_field = FarFieldShape::box;
    EXPECT_FALSE(far_field_sphere(make_o_grid(body, og), on_far).has_value());
    EXPECT_TRUE(on_far.empty());
}

// A boundary layer over the flat top face (z = 0) of a large box: 7 x 7 wall nodes `spacing`
// apart, its lines' nodes at the law's heights up to node 5 (first height 0.02, growth 1.2),
// then on to z = 2 at node 11; the lines with `off(i, j)` at `factor` times those heights
// (at most halfway to z = 2) and leaning by `lean` times their height along x, as the joint
// optimization leaves lines the layer pass gave back. Wall nodes slide, side and far nodes are
// fixed, and so are the off lines' nodes unless `movable`.
template <class Off>
BlockGrid layered_wall(double spacing, double factor, double lean, Off off, bool movable) {
    std::vector<double> z(12, 0.0);
    for (int k = 1; k <= 5; ++k) z[k] = z[k - 1] + 0.02 * std::pow(1.2, k - 1);
    for (int k = 6; k < 12; ++k) z[k] = z[5] + (2 - z[5]) * (k - 5) / 6.0;
    std::vector<bool> on_level;
    BlockGrid grid = placed_block(
        7, 7, 12,
        [&](int i, int j, int k) {
            const bool side = i == 0 || j == 0 || i == 6 || j == 6 || k == 11;
            const bool lifted = off(i, j) && k > 0 && k < 11;
            const double h = lifted ? std::min(factor * z[k], 0.5 * (z[k] + z[11])) : z[k];
            const VertexKind kind = side                 ? VertexKind::fixed
                                    : k == 0             ? VertexKind::slip
                                    : lifted && !movable ? VertexKind::fixed
                                                         : VertexKind::interior;
            return PlacedNode{Vec3(spacing * i + (lifted ? lean * h : 0.0), spacing * j, h), kind};
        },
        on_level);
    grid.blocks[0].face_patch[kmin] = "wall";
    return grid;
}

// Lines left off the law's heights (a patch of 3 x 3, three times too high, leaning) are put
// back on them: every layer node at its height, on the ray from its wall node through its
// line's fifth node (the lean kept), the lines already on the law untouched, the grid valid and
// its worst cell no worse.
TEST(RestoreLayerHeights, LinesOffTheLawAreMovedOntoItsHeights) {
    const Box body(Vec3(0, 0, -50), Vec3(50, 50, 50));  // u = z above its top face
    const WallLayers law{0.02, 1.2, 5};
    const auto off = [](int i, int j) { return i >= 2 && i <= 4 && j >= 2 && j <= 4; };
    BlockGrid grid = layered_wall(1.0, 3.0, 0.3, off, true);
    const BlockGrid start = grid;
    const double worst = measure_quality(to_hex_mesh(grid)).min_scaled_jacobian;
    const LayerHeightsResult r = restore_layer_heights(grid, body, law);
    EXPECT_EQ(r.lines, 9);
    EXPECT_EQ(r.moved, 9);
    EXPECT_EQ(r.within_before, 0);
    EXPECT_EQ(r.within_after, 9);
    const Block& b = grid.blocks[0];
    double d = 0;
    for (int k = 1; k <= 5; ++k) {
        d += 0.02 * std::pow(1.2, k - 1);
        for (int j = 0; j < 7; ++j)
            for (int i = 0; i < 7; ++i) {
                const Vec3 x = grid.points[b.node(i, j, k)];
                if (!off(i, j)) {
                    EXPECT_EQ(x, start.points[b.node(i, j, k)]);
                    continue;
                }
                EXPECT_NEAR(x.z(), d, 1e-12) << i << " " << j << " " << k;
                const Vec3 x0 = grid.points[b.node(i, j, 0)];
                const Vec3 top = start.points[b.node(i, j, 5)] - x0;
                EXPECT_NEAR((x - x0).cross(top).norm(), 0, 1e-12);  // on the ray through node 5
            }
    }
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_TRUE(q.solver_valid());
    EXPECT_GE(q.min_scaled_jacobian, worst);
}

// A line whose neighbours stand far above the law (every line 25 times too high, all but the
// middle one fixed) keeps cells it would shear: brought down to the law beside them (0.1
// apart), its first cells would lean by 78 degrees; it may go part of the way, never so far
// that a cell around it falls below the grid's worst (about 1: flat boxes).
TEST(RestoreLayerHeights, ALineHeldUpByItsNeighboursKeepsItsCells) {
    const Box body(Vec3(0, 0, -50), Vec3(50, 50, 50));
    const WallLayers law{0.02, 1.2, 5};
    BlockGrid grid = layered_wall(
        0.1, 25.0, 0.0, [](int, int) { return true; }, false);
    for (int k = 1; k < 11; ++k) grid.kinds[grid.blocks[0].node(3, 3, k)] = VertexKind::interior;
    const double worst = measure_quality(to_hex_mesh(grid)).min_scaled_jacobian;
    ASSERT_GT(worst, 0.9);
    const LayerHeightsResult r = restore_layer_heights(grid, body, law);
    EXPECT_EQ(r.lines, 49);
    EXPECT_EQ(r.within_after, 0);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_TRUE(q.solver_valid());
    EXPECT_GE(q.min_scaled_jacobian, worst - 1e-12);
}

// In a block walled on two sides the lines from one wall run through the other's layers: a
// line whose nodes another line also moves stays, and the grid with it.
TEST(RestoreLayerHeights, LinesThatShareNodesStay) {
    const Box body(Vec3(0, 0, -50), Vec3(50, 50, 50));
    const WallLayers law{0.02, 1.2, 5};
    const auto off = [](int i, int j) { return i >= 2 && i <= 4 && j >= 2 && j <= 4; };
    BlockGrid grid = layered_wall(1.0, 3.0, 0.3, off, true);
    grid.blocks[0].face_patch[imin] = "wall";
    const BlockGrid start = grid;
    const LayerHeightsResult r = restore_layer_heights(grid, body, law);
    EXPECT_EQ(r.moved, 0);
    EXPECT_EQ(grid.points, start.points);
}

}  // namespace
}  // namespace hexmesh

// refine_grid: topology, nesting and conformity of a refined O-H sphere grid, the refined law
// along wall-normal lines; BlockRefiner,
// the same grid one block at a time.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "grid_checks.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "volume/o_h_grid.h"
#include "volume/refine.h"

using namespace hexmesh;

namespace {

BlockGrid sphere_grid() {
    OHGridOptions o;
    o.cells_per_edge = 6;
    o.wall_cells = 4;
    o.wall_layers = {0.02, 1.2, 2};
    return make_o_h_grid(Sphere(Vec3(0.1, -0.2, 0.3), 1.0), o);
}

// Distinct coarse edges and faces of a grid's cells, by their sorted node ids.
std::pair<Id, Id> count_edges_and_faces(const BlockGrid& grid) {
    std::set<std::array<Id, 2>> edges;
    std::set<std::array<Id, 4>> faces;
    const HexMesh mesh = to_hex_mesh(grid);
    for (Id c = 0; c < mesh.num_cells(); ++c) {
        for (const auto& e : hex_edges) {
            std::array<Id, 2> key{mesh.node(c, e[0]), mesh.node(c, e[1])};
            std::sort(key.begin(), key.end());
            edges.insert(key);
        }
        for (const auto& f : hex_faces) {
            std::array<Id, 4> key{mesh.node(c, f[0]), mesh.node(c, f[1]), mesh.node(c, f[2]),
                                  mesh.node(c, f[3])};
            std::sort(key.begin(), key.end());
            faces.insert(key);
        }
    }
    return {Id(edges.size()), Id(faces.size())};
}

}  // namespace

TEST(RefineGrid, EachBlockGoesFromNToTwoNMinusOneNodesPerDirection) {
    const BlockGrid coarse = sphere_grid();
    const BlockGrid fine = refine_grid(coarse);
    ASSERT_EQ(fine.blocks.size(), coarse.blocks.size());
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        const Dims c = coarse.blocks[b].nodes, f = fine.blocks[b].nodes;
        EXPECT_EQ(f.ni, 2 * c.ni - 1);
        EXPECT_EQ(f.nj, 2 * c.nj - 1);
        EXPECT_EQ(f.nk, 2 * c.nk - 1);
        EXPECT_EQ(fine.blocks[b].name, coarse.blocks[b].name);
        EXPECT_EQ(fine.blocks[b].face_patch, coarse.blocks[b].face_patch);
    }
    EXPECT_EQ(fine.num_cells(), 8 * coarse.num_cells());
}

TEST(RefineGrid, OneNewNodePerCoarseEdgeFaceAndCell) {
    const BlockGrid coarse = sphere_grid();
    const BlockGrid fine = refine_grid(coarse);
    const auto [edges, faces] = count_edges_and_faces(coarse);
    EXPECT_EQ(Id(fine.points.size()),
              Id(coarse.points.size()) + edges + faces + coarse.num_cells());
    EXPECT_EQ(fine.kinds.size(), fine.points.size());
}

TEST(RefineGrid, CoarseNodesKeepTheirIdsAndExactPositionsAtEvenIndices) {
    const BlockGrid coarse = sphere_grid();
    const BlockGrid fine = refine_grid(coarse);
    for (size_t v = 0; v < coarse.points.size(); ++v) {
        ASSERT_EQ(fine.points[v], coarse.points[v]) << v;  // bitwise: the family is nested
        ASSERT_EQ(fine.kinds[v], coarse.kinds[v]) << v;
    }
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        const Block &c = coarse.blocks[b], &f = fine.blocks[b];
        for (int k = 0; k < c.nodes.nk; ++k)
            for (int j = 0; j < c.nodes.nj; ++j)
                for (int i = 0; i < c.nodes.ni; ++i)
                    ASSERT_EQ(f.node(2 * i, 2 * j, 2 * k), c.node(i, j, k));
    }
}

TEST(RefineGrid, InterfacesStayConforming) {
    const BlockGrid coarse = sphere_grid();
    const auto before = test_support::count_faces(to_hex_mesh(coarse));
    const auto after = test_support::count_faces(to_hex_mesh(refine_grid(coarse)));
    EXPECT_EQ(after.over_shared, 0);
    EXPECT_EQ(after.boundary, 4 * before.boundary);  // only the wall, each wall face split in 4
    EXPECT_EQ(after.internal, 4 * before.internal + 12 * coarse.num_cells());
}

TEST(RefineGrid, NoCellIsInverted) {
    const QualityReport q = measure_quality(to_hex_mesh(refine_grid(sphere_grid())));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, 0.3);
}

TEST(RefineGrid, NewWallNodesSlipAndStayCloseToTheSphere) {
    const BlockGrid coarse = sphere_grid();
    const BlockGrid fine = refine_grid(coarse);
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 1.0);
    const Id coarse_slip = std::count(coarse.kinds.begin(), coarse.kinds.end(), VertexKind::slip);
    const Id fine_slip = std::count(fine.kinds.begin(), fine.kinds.end(), VertexKind::slip);
    EXPECT_EQ(fine_slip, 4 * (coarse_slip - 2) + 2);  // V - E + F = 2 on the wall, F x 4
    double worst = 0;
    for (size_t v = coarse.points.size(); v < fine.points.size(); ++v)
        if (fine.kinds[v] == VertexKind::slip)
            worst = std::max(worst, std::abs(sphere.value(fine.points[v])));
    // Cubic interpolation along the wall's grid lines: far below the chordal error of a
    // 6-cell patch edge (about 1 - cos(pi / 24) = 8.6e-3).
    EXPECT_LT(worst, 2e-3);
}

TEST(RefineGrid, GeometricStretchingBecomesItsSquareRoot) {
    // One block, a line of nodes x_m = sum r^l along i: the refined spacing grows by sqrt(r).
    BlockGrid grid;
    const double r = 1.21;
    const int n = 9;
    Block b;
    b.name = "line";
    b.nodes = {n, 2, 2};
    double x = 0, h = 1;
    std::vector<double> xs;
    for (int m = 0; m < n; ++m, x += h, h *= r) xs.push_back(x);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < n; ++i) {
                b.node_ids.push_back(Id(grid.points.size()));
                grid.points.emplace_back(xs[i], j, k);
                grid.kinds.push_back(VertexKind::interior);
            }
    grid.blocks.push_back(b);
    const BlockGrid fine = refine_grid(grid);
    const Block& f = fine.blocks[0];
    for (int i = 4; i + 4 < f.nodes.ni; ++i) {  // away from the quadratic end stencils
        const double a = fine.points[f.node(i + 1, 0, 0)].x() - fine.points[f.node(i, 0, 0)].x();
        const double c =
            fine.points[f.node(i + 2, 0, 0)].x() - fine.points[f.node(i + 1, 0, 0)].x();
        EXPECT_NEAR(c / a, std::sqrt(r), 2e-3) << i;
    }
}

namespace {

// A block whose i lines (2 x 2 of them, 0.5 apart) run through the points `line`, its face
// `wall` (imin or imax) a wall: a line normal to the wall, as in a boundary-layer block.
BlockGrid wall_line_block(const std::vector<Vec3>& line, BlockFace wall) {
    BlockGrid grid;
    Block b;
    b.name = "layers";
    b.nodes = {int(line.size()), 2, 2};
    b.face_patch[wall] = "wall";
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (const Vec3& x : line) {
                b.node_ids.push_back(Id(grid.points.size()));
                grid.points.push_back(x + Vec3(0, 0, 0.5 * j + 0.5 * k));
                grid.kinds.push_back(VertexKind::interior);
            }
    grid.blocks.push_back(b);
    return grid;
}

// Wall distances of `layers` cells from h of ratio r, then `fill` cells of ratio R.
std::vector<double> two_ratio_distances(double h, double r, int layers, double R, int fill) {
    std::vector<double> d = {0};
    for (int m = 0; m < layers + fill; ++m, h *= m < layers ? r : R) d.push_back(d.back() + h);
    return d;
}

}  // namespace

TEST(RefineGrid, WallNormalLinesFollowTheRefinedLawAcrossTheEndOfTheLayers) {
    // 4 layers of ratio 1.21 from 0.01, then 4 cells of ratio 1.7 (the rest of the line grows
    // faster, as wall_distances fills it): 8 fine layers of ratio 1.1 from 0.01 / 2.1, then
    // cells of ratio sqrt(1.7); the spacing grows everywhere. (Cubic stencils in the index
    // made ratios 1.03 and 1.25 in the last layer.) The same with the wall at the other end.
    const std::vector<double> d = two_ratio_distances(0.01, 1.21, 4, 1.7, 4);
    for (const BlockFace wall : {imin, imax}) {
        std::vector<Vec3> line;  // node i at distance d[i] from the wall, or d[n - 1 - i]
        for (size_t i = 0; i < d.size(); ++i)
            line.emplace_back(wall == imin ? d[i] : -d[d.size() - 1 - i], 0, 0);
        const BlockGrid fine = refine_grid(wall_line_block(line, wall));
        const Block& f = fine.blocks[0];
        std::vector<double> h;  // fine cells from the wall
        for (int i = 0; i + 1 < f.nodes.ni; ++i) {
            const int a = wall == imin ? i : f.nodes.ni - 1 - i, b = wall == imin ? a + 1 : a - 1;
            h.push_back((fine.points[f.node(b, 1, 1)] - fine.points[f.node(a, 1, 1)]).norm());
        }
        EXPECT_NEAR(h[0], 0.01 / 2.1, 1e-15) << wall;
        for (size_t m = 0; m + 1 < h.size(); ++m) {
            EXPECT_GE(h[m + 1] / h[m], 1.0) << wall << " " << m;
            if (m < 7) {
                EXPECT_NEAR(h[m + 1] / h[m], 1.1, 1e-12) << wall << " " << m;
            } else if (m >= 8) {
                EXPECT_NEAR(h[m + 1] / h[m], std::sqrt(1.7), 1e-12) << wall << " " << m;
            }
        }
    }
}

TEST(RefineGrid, WallNormalLinesKeepTheirCurvature) {
    // The line an arc of the unit circle, its arc length the two-ratio law. Each new node is
    // where the grid without a wall puts it (the cubic of the line), moved along its coarse
    // cell's chord only, to the law's fraction of it: its offset from the chord, the arc's
    // curvature, is kept (up to 4.6e-3 in the last cell: a node on the chord would be that
    // far inside the circle).
    const std::vector<double> d = two_ratio_distances(0.01, 1.21, 4, 1.7, 4);
    std::vector<Vec3> line;
    for (double t : d) line.emplace_back(std::cos(t), std::sin(t), 0);
    const BlockGrid coarse = wall_line_block(line, imin);
    BlockGrid no_wall = coarse;
    no_wall.blocks[0].face_patch[imin] = "";
    const BlockGrid fine = refine_grid(coarse), cubic = refine_grid(no_wall);
    const Block& f = fine.blocks[0];
    for (int i = 1; i < f.nodes.ni; i += 2) {
        const Vec3 a = line[i / 2], chord = line[i / 2 + 1] - a;
        const Vec3 x = fine.points[f.node(i, 0, 0)], y = cubic.points[f.node(i, 0, 0)];
        EXPECT_LT((x - y).cross(chord).norm(), 1e-12) << i;  // x - y along the chord
        const Vec3 offset = (x - a) - (x - a).dot(chord) / chord.squaredNorm() * chord;
        EXPECT_GT(offset.norm(), 0.1 * (1 - std::cos(chord.norm() / 2))) << i;
    }
}

TEST(RefineGrid, ThinLayersUnderLongCellsStayNearTheirChords) {
    // 3 layers from 1e-7 (ratio 1.2) under cells growing 100-fold (a thin first layer under a
    // coarse wall), the line an arc of radius 0.2 (it turns by 42 degrees, less than a kink):
    // each new node within (1/2) tan(45 / 4 degrees) of its coarse cell's chord length from
    // the chord, at the refined law's fraction of it. The cubic stencil in the index put a new
    // node a share of the long cells beyond off its chord (3.1e-3 off a chord of 1.4e-3): a
    // refined sphere with a first height of 1e-7 came out with 1512 inverted cells.
    const std::vector<double> d = two_ratio_distances(1e-7, 1.2, 3, 100, 3);
    std::vector<Vec3> line;
    for (double t : d) line.emplace_back(0.2 * std::cos(t / 0.2), 0.2 * std::sin(t / 0.2), 0);
    const BlockGrid fine = refine_grid(wall_line_block(line, imin));
    const Block& f = fine.blocks[0];
    const auto length = [&](size_t m) { return (line[m + 1] - line[m]).norm(); };
    for (int i = 1; i < f.nodes.ni; i += 2) {
        const size_t m = size_t(i / 2);
        const Vec3 a = line[m], chord = line[m + 1] - a;
        const Vec3 x = fine.points[f.node(i, 0, 0)] - a;
        const Vec3 offset = x - x.dot(chord) / chord.squaredNorm() * chord;
        EXPECT_LE(offset.norm(), 0.0995 * chord.norm()) << i;
        // The law's fraction 1 / (1 + rho), rho = sqrt(L_m / L_(m-1)) (sqrt(L_1 / L_0) at the
        // wall).
        const double rho =
            m > 0 ? std::sqrt(length(m) / length(m - 1)) : std::sqrt(length(1) / length(0));
        EXPECT_NEAR(x.dot(chord) / chord.squaredNorm(), 1 / (1 + rho), 1e-9) << i;
    }
}

TEST(RefineGrid, LinesTurningAtACreaseStayOnTheirSideOfIt) {
    // A block whose i lines turn by 90 degrees at i = 3 (along x, then along y), like the
    // lines over a box's edge: the new nodes lie on the two straight legs, none overshoots the
    // corner (a cubic stencil across it would move the two next to it by 1/16 of a cell).
    BlockGrid grid;
    const int n = 7;
    Block b;
    b.name = "bent";
    b.nodes = {n, 2, 2};
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < n; ++i) {
                b.node_ids.push_back(Id(grid.points.size()));
                const double s = 0.2 * j;  // the j = 1 line runs inside the j = 0 one
                grid.points.push_back(i < 3 ? Vec3(i, s, k) : Vec3(3 - s, i - 3 + s, k));
                grid.kinds.push_back(VertexKind::interior);
            }
    grid.blocks.push_back(b);
    const BlockGrid fine = refine_grid(grid);
    const Block& f = fine.blocks[0];
    for (int j = 0; j < f.nodes.nj; j += 2)
        for (int i = 0; i < f.nodes.ni; ++i) {
            const Vec3& x = fine.points[f.node(i, j, 0)];
            const double s = 0.1 * j;
            if (i <= 6)
                EXPECT_NEAR(x.y(), s, 1e-12) << i << " " << j;
            else
                EXPECT_NEAR(x.x(), 3 - s, 1e-12) << i << " " << j;
        }
}

// Block by block: every fine block holds the fine grid's points at its ids; a new node on a
// block interface is placed once, by its first block, and every block holding it gets that
// position, even when placement would give another one each time.
TEST(BlockRefiner, BlocksAreTheFineGridsAndPlaceEachFaceNodeOnce) {
    const BlockGrid coarse = sphere_grid();
    const BlockGrid fine = refine_grid(coarse);
    BlockRefiner refiner(coarse);
    EXPECT_EQ(refiner.num_points(), Id(fine.points.size()));
    EXPECT_EQ(refiner.num_cells(), fine.num_cells());
    std::atomic<int> calls{0};
    const auto place = [&](const Vec3& x, VertexKind) {
        return Vec3(x + Vec3(0, 0, 1e-3 * ++calls));
    };
    std::map<Id, Vec3> placed;  // face nodes by fine id
    std::map<Id, int> holders;
    for (size_t b = 0; b < coarse.blocks.size(); ++b) {
        const RefinedBlock piece = refiner.refine(b, place);
        ASSERT_EQ(piece.grid.blocks.size(), 1u);
        const Block& block = piece.grid.blocks[0];
        EXPECT_EQ(block.nodes.count(), fine.blocks[b].nodes.count());
        EXPECT_EQ(piece.ids, fine.blocks[b].node_ids);
        for (size_t m = 0; m < piece.ids.size(); ++m) {
            const Id v = piece.ids[m];
            EXPECT_EQ(piece.grid.kinds[m], fine.kinds[v]);
            EXPECT_EQ(piece.coarse[m], v < Id(coarse.points.size()));
            const Vec3 x = piece.grid.points[m];
            const bool moved = x != fine.points[v];
            if (piece.coarse[m]) {
                EXPECT_EQ(x, coarse.points[v]);
                continue;
            }
            const Dims& d = block.nodes;
            const int i = int(m % d.ni), j = int(m / d.ni % d.nj), k = int(m / d.ni / d.nj);
            const bool on_face =
                i == 0 || j == 0 || k == 0 || i == d.ni - 1 || j == d.nj - 1 || k == d.nk - 1;
            // Inside the block: not placed (moved, if at all, along with a wall node's line).
            if (!moved || !on_face) continue;
            const auto [it, first] = placed.try_emplace(v, x);
            if (!first) {
                EXPECT_EQ(it->second, x) << "fine node " << v;
            }
            if (++holders[v] > 1) {
                EXPECT_TRUE(piece.shared[m]) << "fine node " << v;
            }
        }
    }
    EXPECT_EQ(calls.load(), int(placed.size()));
    EXPECT_GT(
        std::count_if(holders.begin(), holders.end(), [](const auto& h) { return h.second > 1; }),
        0);
    EXPECT_THROW(refiner.refine(0), std::logic_error);  // each block once, in order
}

// Placement moves a new wall node (onto the body, in `refine`): the new nodes of its
// wall-normal line follow by d (1 - s / S), so the line's cells all stretch by 1 + |d| / S:
// its growth ratios stay the law's and its first cell keeps its thickness (it would grow by
// |d|, 42 % here, if the line stayed where interpolated).
TEST(BlockRefiner, WallNormalLinesFollowTheirPlacedWallNode) {
    const std::vector<double> d = two_ratio_distances(0.01, 1.21, 4, 1.7, 4);
    std::vector<Vec3> line;
    for (double x : d) line.emplace_back(x, 0, 0);
    const Vec3 move(-0.002, 0, 0);  // out of the grid
    const BlockGrid coarse = wall_line_block(line, imin);
    BlockRefiner refiner(coarse);
    const RefinedBlock piece = refiner.refine(0, [&](const Vec3& x, VertexKind kind) {
        return kind == VertexKind::slip ? Vec3(x + move) : x;
    });
    const Block& f = piece.grid.blocks[0];
    ASSERT_EQ(piece.grid.kinds[f.nodes.flat(0, 1, 1)], VertexKind::slip);  // a new wall node
    std::vector<double> h;  // the fine cells of its line
    for (int i = 0; i + 1 < f.nodes.ni; ++i)
        h.push_back(piece.grid.points[f.nodes.flat(i + 1, 1, 1)].x() -
                    piece.grid.points[f.nodes.flat(i, 1, 1)].x());
    const double stretch = 1 + 0.002 / d.back();
    EXPECT_NEAR(h[0], 0.01 / 2.1 * stretch, 1e-15);
    for (size_t m = 0; m < 7; ++m) EXPECT_NEAR(h[m + 1] / h[m], 1.1, 1e-12) << m;
    EXPECT_NEAR(h.back(),
                (d.back() - d[d.size() - 2]) * std::sqrt(1.7) / (1 + std::sqrt(1.7)) * stretch,
                1e-15);
}

// Two one-cell blocks side by side (x in [0, 1] and [1, 2]), numbered by hand: block 0's 19 new
// nodes take ids 12..30 in its flat order, block 1 takes the 5 new nodes of the shared face
// from block 0 and numbers its 14 others 31..44. An empty block (as a reader may hand over)
// passes through; kinds not sized like the points are refused.
TEST(BlockRefiner, TwoBlocksNumberedByHand) {
    BlockGrid coarse;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) coarse.points.push_back(Vec3(x, y, z));
    coarse.kinds.assign(coarse.points.size(), VertexKind::interior);
    coarse.blocks.push_back(Block{});  // no nodes
    for (int b = 0; b < 2; ++b) {
        Block block;
        block.name = "b" + std::to_string(b);
        block.nodes = {2, 2, 2};
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) block.node_ids.push_back(Id(b + i + 3 * (j + 2 * k)));
        coarse.blocks.push_back(block);
    }
    BlockRefiner refiner(coarse);
    EXPECT_EQ(refiner.num_points(), 45);
    EXPECT_EQ(refiner.refine(0).ids.size(), 0u);
    const RefinedBlock a = refiner.refine(1), b = refiner.refine(2);
    const Dims f = {3, 3, 3};
    Id next = 12;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const Id m = f.flat(i, j, k);
                const bool old = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
                EXPECT_EQ(a.ids[m], old ? Id(i / 2 + 3 * (j / 2 + 2 * (k / 2))) : next++);
                EXPECT_EQ(a.shared[m], !old && i == 2);
            }
    EXPECT_EQ(next, 31);
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const Id m = f.flat(i, j, k);
                const bool old = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
                if (old) {
                    EXPECT_EQ(b.ids[m], Id(1 + i / 2 + 3 * (j / 2 + 2 * (k / 2))));
                } else if (i == 0) {  // the shared face: block 0's node at i = 2
                    EXPECT_EQ(b.ids[m], a.ids[f.flat(2, j, k)]);
                    EXPECT_EQ(b.grid.points[m], a.grid.points[f.flat(2, j, k)]);
                    EXPECT_TRUE(b.shared[m]);
                } else {
                    EXPECT_EQ(b.ids[m], next++);
                    EXPECT_FALSE(b.shared[m]);
                }
                EXPECT_EQ(b.grid.points[m], Vec3(1 + 0.5 * i, 0.5 * j, 0.5 * k));
            }
    EXPECT_EQ(next, 45);
    const BlockGrid fine = refine_grid(coarse);
    EXPECT_EQ(fine.points.size(), 45u);
    EXPECT_EQ(fine.blocks.size(), 3u);
    EXPECT_EQ(fine.num_cells(), 16);

    coarse.kinds.clear();
    EXPECT_THROW(BlockRefiner{coarse}, std::invalid_argument);
}

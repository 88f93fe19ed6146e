// The surface pass: the wall grid alone on u = 0 with the 2D functional, the volume following.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "hexmesh/pipeline/surface_grid.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "volume/o_h_grid.h"
#include "volume/wall_lines.h"

using namespace hexmesh;

namespace {

OHGridOptions options(int n) {
    OHGridOptions o;
    o.cells_per_edge = n;
    o.wall_cells = 4;
    return o;
}

// Wall quads whose corners turn the other way than the face's majority, seen along grad u,
// and the largest deviation of a wall-quad corner angle from 90 degrees.
struct WallQuads {
    int folded = 0;
    double worst_angle = 0;
};

WallQuads wall_quads(const BlockGrid& grid, const ImplicitFunction& body) {
    WallQuads w;
    for (const WallFace& f : wall_faces(grid)) {
        int positive = 0, negative = 0;
        for (int b = 0; b + 1 < f.nq; ++b)
            for (int a = 0; a + 1 < f.np; ++a) {
                const std::array<Id, 4> q = {f.node(a, b, 0), f.node(a + 1, b, 0),
                                             f.node(a + 1, b + 1, 0), f.node(a, b + 1, 0)};
                for (int c = 0; c < 4; ++c) {
                    const Vec3& x = grid.points[q[c]];
                    const Vec3 e1 = grid.points[q[(c + 1) % 4]] - x,
                               e2 = grid.points[q[(c + 3) % 4]] - x;
                    const double turn = body.gradient(x).dot(e1.cross(e2));
                    (turn > 0 ? positive : negative)++;
                    const double angle =
                        std::acos(e1.normalized().dot(e2.normalized())) * 180 / M_PI;
                    w.worst_angle = std::max(w.worst_angle, std::abs(angle - 90));
                }
            }
        w.folded += std::min(positive, negative);
    }
    return w;
}

}  // namespace

TEST(OptimizeWallSurface, UntanglesAFoldedWallGridOnTheSurface) {
    const Sphere sphere(Vec3(0.1, 0, 0), 1.0);
    OHGridOptions grid_options = options(8);
    BlockGrid grid = make_o_h_grid(sphere, grid_options);
    // Two neighbouring wall nodes of one face swap places: the quads around them fold.
    const WallFace f = wall_faces(grid)[0];
    const Id a = f.node(3, 4, 0), b = f.node(4, 4, 0);
    std::swap(grid.points[a], grid.points[b]);
    ASSERT_GT(wall_quads(grid, sphere).folded, 0);
    const std::vector<Vec3> before = grid.points;

    untangle::UntangleOptions o;
    o.max_optimize_iterations = 5;
    const SurfaceOptimizationResult r = optimize_wall_surface(grid, sphere, o);
    EXPECT_EQ(r.nodes, 6 * 8 * 8 + 2);
    EXPECT_EQ(r.triangles, 4 * 6 * 8 * 8);
    EXPECT_GT(r.solve.inverted_before, 0);
    EXPECT_EQ(r.solve.inverted_after, 0);
    EXPECT_EQ(wall_quads(grid, sphere).folded, 0);
    const double h = grid_length_scale(sphere, 8);
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip) {
            EXPECT_LT(std::abs(sphere.value(grid.points[v])), 1e-9 * h);
        }
    EXPECT_GT((grid.points[a] - before[a]).norm(), 0.5 * h);
    EXPECT_GT(r.max_move, 0.5);
    // Only wall nodes moved; the grid built again from them has no inverted cell.
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] != VertexKind::slip) {
            EXPECT_EQ(grid.points[v], before[v]);
        }
    grid_options.wall_from = &grid.points;
    EXPECT_EQ(measure_quality(to_hex_mesh(make_o_h_grid(sphere, grid_options))).inverted_cells, 0);
}

TEST(OptimizeWallSurface, SquaresTheWallCellsOfAnEllipsoid) {
    // The cube-sphere directions projected radially onto a 3:2:1 ellipsoid give skewed wall
    // quads; the 2D functional drives their corners towards right angles on the surface.
    const Ellipsoid body(Vec3::Zero(), Vec3(1.5, 1.0, 0.5));
    BlockGrid grid = make_o_h_grid(body, options(10));
    const WallQuads before = wall_quads(grid, body);
    untangle::UntangleOptions o;
    o.max_optimize_iterations = 10;
    const SurfaceOptimizationResult r = optimize_wall_surface(grid, body, o);
    const WallQuads after = wall_quads(grid, body);
    EXPECT_EQ(r.solve.inverted_after, 0);
    EXPECT_LT(r.solve.energy_after, std::numeric_limits<double>::infinity());
    EXPECT_LT(after.worst_angle, before.worst_angle - 5)
        << before.worst_angle << " -> " << after.worst_angle;
    EXPECT_EQ(after.folded, 0);
}

namespace {

// The largest distance of a wall quad's centre to the body, over the quad's size (the square
// root of its area, as two triangles).
double worst_quad_gap(const BlockGrid& grid, const ImplicitFunction& body) {
    double worst = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int b = 0; b + 1 < f.nq; ++b)
            for (int a = 0; a + 1 < f.np; ++a) {
                const Vec3 &x0 = grid.points[f.node(a, b, 0)],
                           &x1 = grid.points[f.node(a + 1, b, 0)],
                           &x2 = grid.points[f.node(a + 1, b + 1, 0)],
                           &x3 = grid.points[f.node(a, b + 1, 0)];
                const double area =
                    ((x1 - x0).cross(x3 - x0).norm() + (x1 - x2).cross(x3 - x2).norm()) / 2;
                worst = std::max(worst,
                                 std::abs(body.value((x0 + x1 + x2 + x3) / 4)) / std::sqrt(area));
            }
    return worst;
}

}  // namespace

// A long ellipsoid (3 : 0.4 : 0.4) through radial projection: its tips' wall quads bridge the
// most (the worst centre 0.2 quad sizes off the body). The surface pass alone squares the
// quads and leaves the tips' worse (0.21); with each quad held to the body (weight 100) the
// tips keep more nodes and the worst gap falls below as placed (0.19).
TEST(OptimizeWallSurface, WallQuadsHeldToTheBodyFollowItsTipsCloser) {
    const Ellipsoid body(Vec3::Zero(), Vec3(3.0, 0.4, 0.4));
    std::vector<double> gap;
    double placed = 0;
    for (double fidelity : {0.0, 100.0}) {
        BlockGrid grid = make_o_h_grid(body, options(10));
        placed = worst_quad_gap(grid, body);
        untangle::UntangleOptions o;
        o.max_optimize_iterations = 10;
        const SurfaceOptimizationResult r = optimize_wall_surface(grid, body, o, fidelity);
        EXPECT_EQ(r.solve.inverted_after, 0);
        EXPECT_FALSE(r.solve.wall_let_go);
        gap.push_back(worst_quad_gap(grid, body));
    }
    EXPECT_GT(gap[0], placed);
    EXPECT_LT(gap[1], placed - 0.005) << placed;
}

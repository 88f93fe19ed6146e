#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "hexmesh/quality/wall_metrics.h"
#include "surface/analytic.h"
#include "tests/surface/sample_surfaces.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"
#include "volume/single_block_grid.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

using namespace hexmesh;

namespace {

constexpr double pi = 3.14159265358979323846;
const WallLayers law{0.01, 1.2, 4};

OHGridOptions sphere_options() {
    OHGridOptions o;
    o.cells_per_edge = 12;
    o.wall_cells = 8;
    o.wall_layers = law;
    return o;
}

// Wall quads of the O-H grid's wall blocks: nodes (i,j), (i+1,j), (i+1,j+1), (i,j+1) of
// face kmax, the order hausdorff_to_surface splits into triangles (a,b,c) and (a,c,d).
std::vector<std::array<Id, 4>> wall_quads(const BlockGrid& grid) {
    std::vector<std::array<Id, 4>> quads;
    for (const Block& b : grid.blocks) {
        if (b.face_patch[kmax] != "wall") continue;
        const int k = b.nodes.nk - 1;
        for (int j = 0; j + 1 < b.nodes.nj; ++j)
            for (int i = 0; i + 1 < b.nodes.ni; ++i)
                quads.push_back({b.node(i, j, k), b.node(i + 1, j, k), b.node(i + 1, j + 1, k),
                                 b.node(i, j + 1, k)});
    }
    return quads;
}

// First-edge node pairs (x0 id, x1 id) of the O-H grid's wall lines, each pair once.
std::map<Id, Id> first_edges(const BlockGrid& grid) {
    std::map<Id, Id> edges;  // x1 -> x0
    for (const Block& b : grid.blocks) {
        if (b.face_patch[kmax] != "wall") continue;
        const int k = b.nodes.nk - 1;
        for (int j = 0; j < b.nodes.nj; ++j)
            for (int i = 0; i < b.nodes.ni; ++i) edges[b.node(i, j, k - 1)] = b.node(i, j, k);
    }
    return edges;
}

// Largest depth below the sphere of a triangle with its corners on it: R - sqrt(R^2 - rho^2),
// rho the circumradius (the triangle's plane is sqrt(R^2 - rho^2) from the centre).
double sag(const Vec3& a, const Vec3& b, const Vec3& c, double radius) {
    const double area2 = (b - a).cross(c - a).norm();
    const double rho = (a - b).norm() * (b - c).norm() * (c - a).norm() / (2 * area2);
    return radius - std::sqrt(radius * radius - rho * rho);
}

// u = |x_axis| - 1: the slab between the planes x_axis = -1 and x_axis = 1.
class Slab : public ImplicitFunction {
  public:
    explicit Slab(int axis) : axis_(axis) {}
    double value(const Vec3& p) const override { return std::abs(p[axis_]) - 1; }
    Vec3 gradient(const Vec3& p) const override {
        return (p[axis_] < 0 ? -1.0 : 1.0) * Vec3::Unit(axis_);
    }
    Box3 bounds() const override { return {Vec3::Constant(-1), Vec3::Constant(1)}; }

  private:
    int axis_;
};

// Adds a block of the tensor lattice x[0] x x[1] x x[2] with its own nodes.
Block& add_lattice_block(BlockGrid& grid, const std::array<std::vector<double>, 3>& x) {
    Block b{"box", {int(x[0].size()), int(x[1].size()), int(x[2].size())}, {}, {}};
    for (int k = 0; k < b.nodes.nk; ++k)
        for (int j = 0; j < b.nodes.nj; ++j)
            for (int i = 0; i < b.nodes.ni; ++i) {
                b.node_ids.push_back(Id(grid.points.size()));
                grid.points.emplace_back(x[0][i], x[1][j], x[2][k]);
                grid.kinds.push_back(VertexKind::interior);
            }
    grid.blocks.push_back(std::move(b));
    return grid.blocks.back();
}

// Three blocks around the slab of `axis`: one inside with walls on both faces of the axis,
// one on each side outside with its wall on the face touching the slab. Other axes: 4
// uniform cells on [0, 1]. Every wall line carries the law.
BlockGrid slab_grid(int axis, const WallLayers& layers) {
    const std::vector<double> d = wall_distances(2.0, 8, layers);
    std::array<std::vector<double>, 3> inside, above, below;
    for (int a = 0; a < 3; ++a) inside[a] = above[a] = below[a] = uniform_distances(1.0, 4);
    inside[axis] = {};
    for (double t : two_sided_distances(2.0, 10, layers)) inside[axis].push_back(-1 + t);
    above[axis] = below[axis] = {};
    for (double t : d) above[axis].push_back(1 + t);
    for (auto it = d.rbegin(); it != d.rend(); ++it) below[axis].push_back(-1 - *it);

    BlockGrid grid;
    Block& in = add_lattice_block(grid, inside);
    in.face_patch[2 * axis] = in.face_patch[2 * axis + 1] = "wall";
    add_lattice_block(grid, above).face_patch[2 * axis] = "wall";
    add_lattice_block(grid, below).face_patch[2 * axis + 1] = "wall";
    return grid;
}

}  // namespace

TEST(WallMetrics, SphereOHGridFollowsTheLawAndIsOrthogonal) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    const WallQuality w = measure_wall(grid, sphere, law);
    const int n = 12;
    EXPECT_EQ(w.wall_cells, 6 * n * n);
    EXPECT_NEAR(w.first_layer_min, 0.01, 1e-6 * 0.01);
    EXPECT_NEAR(w.first_layer_max, 0.01, 1e-6 * 0.01);
    EXPECT_NEAR(w.first_layer_mean, 0.01, 1e-6 * 0.01);
    EXPECT_EQ(w.first_layer_target, 0.01);
    EXPECT_EQ(w.first_layer_within_10_percent, 1.0);
    // layers - 1 = 3 ratios on each of the 6 (n+1)^2 lines.
    EXPECT_EQ(w.growth_ratios, 6 * (n + 1) * (n + 1) * 3);
    EXPECT_NEAR(w.growth_ratio_min, 1.2, 1e-6 * 1.2);
    EXPECT_NEAR(w.growth_ratio_max, 1.2, 1e-6 * 1.2);
    EXPECT_EQ(w.growth_ratio_target, 1.2);
    EXPECT_EQ(w.growth_ratio_within_5_percent, 1.0);
    EXPECT_LT(w.orthogonality_max_deg, 1e-6);
    EXPECT_FALSE(w.hausdorff.has_value());
}

TEST(WallMetrics, ExteriorSphereOGridHasPositiveThickness) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 1.0);
    OGridOptions o;
    o.cells_per_edge = 8;
    o.layers = 12;
    o.wall_layers = law;
    o.far_field_size = 5;
    const WallQuality w = measure_wall(make_o_grid(sphere, o), sphere, law);
    EXPECT_EQ(w.wall_cells, 6 * 8 * 8);
    EXPECT_NEAR(w.first_layer_min, 0.01, 1e-6 * 0.01);  // grid outside u = 0: normal +grad u
    EXPECT_NEAR(w.first_layer_max, 0.01, 1e-6 * 0.01);
    EXPECT_NEAR(w.growth_ratio_min, 1.2, 1e-6 * 1.2);
    EXPECT_NEAR(w.growth_ratio_max, 1.2, 1e-6 * 1.2);
    EXPECT_LT(w.orthogonality_max_deg, 1e-6);
}

TEST(WallMetrics, TangentialShiftOfOneFirstNodeGivesItsAngle) {
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 1.0);
    BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    const Block& b = grid.blocks[1];  // wall_xmin; (5, 5) is inside its face, on no other block
    ASSERT_EQ(b.face_patch[kmax], "wall");
    const int k = b.nodes.nk - 1;
    const Vec3 normal = (grid.points[b.node(5, 5, k)] - c).normalized();
    const Vec3 tangent = normal.cross(Vec3(0.3, 0.5, 0.8)).normalized();
    const double shift = 0.004;
    grid.points[b.node(5, 5, k - 1)] += shift * tangent;

    const WallQuality w = measure_wall(grid, sphere, law);
    const double expected = std::atan(shift / 0.01) * 180 / pi;
    EXPECT_NEAR(w.orthogonality_max_deg, expected, 1e-6);
    EXPECT_NEAR(w.orthogonality_mean_deg, expected / (6 * 13 * 13), 1e-6);
    // A tangential move leaves the projection on the normal unchanged.
    EXPECT_NEAR(w.first_layer_min, 0.01, 1e-6 * 0.01);
    EXPECT_NEAR(w.first_layer_max, 0.01, 1e-6 * 0.01);
}

// A first-layer node pushed 0.05 out through the wall (the law's first edge is 0.01 in): the 4
// wall cells around its line have thickness (3 0.01 - 0.05) / 4 = -0.005, through the wall.
TEST(WallMetrics, AFirstNodeOutThroughTheWallPutsItsFourCellsThroughIt) {
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 1.0);
    BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    EXPECT_EQ(measure_wall(grid, sphere, law).cells_through_wall, 0);
    const Block& b = grid.blocks[1];  // wall_xmin; (5, 5) is inside its face, on no other block
    ASSERT_EQ(b.face_patch[kmax], "wall");
    const int k = b.nodes.nk - 1;
    const Vec3 wall = grid.points[b.node(5, 5, k)];
    grid.points[b.node(5, 5, k - 1)] = wall + 0.05 * (wall - c).normalized();

    const WallQuality w = measure_wall(grid, sphere, law);
    EXPECT_EQ(w.cells_through_wall, 4);
    EXPECT_NEAR(w.first_layer_min, -0.005, 1e-4);
    // The thinnest is one of the four: its wall face's centre within a wall cell of the node.
    const double cell = (grid.points[b.node(6, 5, k)] - wall).norm();
    EXPECT_LT((w.first_layer_min_at - wall).norm(), cell);
    EXPECT_GT((w.first_layer_min_at - wall).norm(), 0.3 * cell);
}

TEST(WallMetrics, MisScaledFirstLayerIsNeverWithinTenPercent) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    for (const auto& [x1, x0] : first_edges(grid))
        grid.points[x1] = grid.points[x0] + 1.2 * (grid.points[x1] - grid.points[x0]);
    const WallQuality w = measure_wall(grid, sphere, law);
    EXPECT_NEAR(w.first_layer_min, 0.012, 1e-6 * 0.012);
    EXPECT_NEAR(w.first_layer_max, 0.012, 1e-6 * 0.012);
    EXPECT_EQ(w.first_layer_within_10_percent, 0.0);
    // Edges 0.012, 0.010, 0.0144, 0.01728: ratios 0.833, 1.44, then 1.2 as the law says.
    EXPECT_NEAR(w.growth_ratio_min, 0.010 / 0.012, 1e-6);
    EXPECT_NEAR(w.growth_ratio_max, 1.44, 1e-6);
    EXPECT_NEAR(w.growth_ratio_within_5_percent, 1.0 / 3.0, 1e-12);
}

TEST(WallMetrics, LinesLaidAlongBisectorsAtABoxsCreasesHaveTheLawsHeight) {
    // The O-H grid of a box: its patch edges run along the box's edges, so every wall node on
    // them sits on a crease (or corner), and the laid lines there leave along the bisector,
    // sqrt(2) (sqrt(3)) times the law's height long, at that height above each face.
    const Box box(Vec3(0.1, -0.2, 0.3), Vec3(1.0, 0.8, 0.6));
    BlockGrid grid = make_o_h_grid(box, sphere_options());
    const std::vector<bool> laid = extrude_wall_layers(grid, box, law, 0);
    ASSERT_EQ(Id(std::count(laid.begin(), laid.end(), true)), 6 * 12 * 12 * 5 + 2 * 5);
    const WallQuality w = measure_wall(grid, box, law);
    EXPECT_NEAR(w.first_layer_min, 0.01, 1e-9);
    EXPECT_NEAR(w.first_layer_max, 0.01, 1e-9);
    EXPECT_EQ(w.first_layer_within_10_percent, 1.0);
    // The lines leave the edges and corners along the bisector of the faces meeting there:
    // orthogonal to the wall as far as a line there can be.
    EXPECT_LT(w.orthogonality_max_deg, 1e-6);

    // A corner's line turned onto one face's normal (into the box: the grid is inside) is
    // acos(1 / sqrt(3)) off the bisector.
    const auto corner =
        std::max_element(grid.points.begin(), grid.points.end(),
                         [](const Vec3& a, const Vec3& b) { return a.sum() < b.sum(); });
    const Id x0 = Id(corner - grid.points.begin());
    for (const Block& b : grid.blocks)
        for (const WallFace& f : wall_faces(b))
            for (int q = 0; q < f.nq; ++q)
                for (int p = 0; p < f.np; ++p)
                    if (f.node(p, q, 0) == x0)
                        grid.points[f.node(p, q, 1)] = grid.points[x0] - 0.01 * Vec3::UnitX();
    const WallQuality turned = measure_wall(grid, box, law);
    EXPECT_NEAR(turned.orthogonality_max_deg, std::acos(1 / std::sqrt(3.0)) * 180 / pi, 1e-6);
}

TEST(WallMetrics, EveryFaceDirectionInsideAndOutside) {
    const WallLayers layers{0.05, 1.3, 3};
    for (int axis = 0; axis < 3; ++axis) {
        SCOPED_TRACE(axis);
        const Slab slab(axis);
        const WallQuality w = measure_wall(slab_grid(axis, layers), slab, layers);
        EXPECT_EQ(w.wall_cells, 4 * 16);
        EXPECT_NEAR(w.first_layer_min, 0.05, 1e-12);
        EXPECT_NEAR(w.first_layer_max, 0.05, 1e-12);
        EXPECT_EQ(w.growth_ratios, 4 * 25 * 2);
        EXPECT_NEAR(w.growth_ratio_min, 1.3, 1e-12);
        EXPECT_NEAR(w.growth_ratio_max, 1.3, 1e-12);
        EXPECT_LT(w.orthogonality_max_deg, 1e-12);
    }
}

TEST(WallMetrics, WithoutALawGrowthCoversWholeLinesAndTargetsAreUnknown) {
    const WallLayers layers{0.05, 1.3, 3};
    const WallQuality w = measure_wall(slab_grid(2, layers), Slab(2), WallLayers{});
    EXPECT_EQ(w.first_layer_target, 0.0);
    EXPECT_EQ(w.first_layer_within_10_percent, 0.0);
    EXPECT_EQ(w.growth_ratio_target, 0.0);
    // Inside: 2 faces of lines of 10 edges; outside: 2 faces of lines of 8 edges.
    EXPECT_EQ(w.growth_ratios, 2 * 25 * 9 + 2 * 25 * 7);
    EXPECT_NEAR(w.first_layer_min, 0.05, 1e-12);
    EXPECT_GT(w.growth_ratio_max, 1.3);  // past the layers the lines stretch faster
}

TEST(WallMetrics, HausdorffToATriangulatedSphereIsBelowTheSag) {
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    const TriangleSurface uv = test::uv_sphere(c, 1.0, 48, 24);

    // Both triangulations are inscribed in the sphere: a point of either is within the
    // larger sag of the sphere, and so (along its radius) of the other triangulation.
    double bound = 0;
    for (const auto& t : uv.triangles)
        bound = std::max(bound, sag(uv.points[t[0]], uv.points[t[1]], uv.points[t[2]], 1.0));
    const double uv_sag = bound;
    for (const auto& q : wall_quads(grid)) {
        const Vec3 a = grid.points[q[0]], b = grid.points[q[1]], cc = grid.points[q[2]],
                   d = grid.points[q[3]];
        bound = std::max({bound, sag(a, b, cc, 1.0), sag(a, cc, d, 1.0)});
    }
    const HausdorffDistance h = hausdorff_to_surface(grid, uv);
    EXPECT_LE(h.grid_to_surface, uv_sag + 1e-9);
    EXPECT_LE(h.hausdorff, bound + 1e-9);
    EXPECT_GT(h.hausdorff, 0.0);
    EXPECT_EQ(h.hausdorff, std::max(h.grid_to_surface, h.surface_to_grid));
}

TEST(WallMetrics, HausdorffToATranslatedCopyIsTheTranslation) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    // The grid's own wall triangulation moved by t: the extreme wall node in direction -t is
    // |t| from the copy and no point is farther, both ways.
    const Vec3 t(0.03, -0.02, 0.01);
    TriangleSurface moved;
    for (const Vec3& p : grid.points) moved.points.push_back(p + t);
    for (const auto& q : wall_quads(grid)) {
        moved.triangles.push_back({int(q[0]), int(q[1]), int(q[2])});
        moved.triangles.push_back({int(q[0]), int(q[2]), int(q[3])});
    }
    const HausdorffDistance h = hausdorff_to_surface(grid, moved);
    EXPECT_NEAR(h.grid_to_surface, t.norm(), 1e-9);
    EXPECT_NEAR(h.surface_to_grid, t.norm(), 1e-9);
    EXPECT_NEAR(h.hausdorff, t.norm(), 1e-9);
}

// surface_to_wall_in_cells is the in-cells part of hausdorff_to_surface: the same figures on
// the same grid (an O-H grid of a unit sphere against a coarse UV sphere a little larger), the
// other distances left 0.
TEST(WallMetrics, SurfaceToWallInCellsIsHausdorffsInCellsPart) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, sphere_options());
    const TriangleSurface uv = test::uv_sphere(Vec3::Zero(), 1.05, 12, 6);
    const HausdorffDistance all = hausdorff_to_surface(grid, uv);
    const HausdorffDistance cells = surface_to_wall_in_cells(grid, uv);
    EXPECT_GT(all.surface_in_cells_max, 0.0);
    EXPECT_EQ(cells.surface_in_cells_max, all.surface_in_cells_max);
    EXPECT_EQ(cells.surface_in_cells_p99, all.surface_in_cells_p99);
    EXPECT_EQ(cells.surface_in_cells_at, all.surface_in_cells_at);
    EXPECT_EQ(cells.surface_in_cells_distance, all.surface_in_cells_distance);
    EXPECT_EQ(cells.hausdorff, 0.0);
    BlockGrid no_wall;
    add_lattice_block(no_wall,
                      {uniform_distances(1, 2), uniform_distances(1, 2), uniform_distances(1, 2)});
    EXPECT_THROW(surface_to_wall_in_cells(no_wall, uv), std::invalid_argument);
}

TEST(WallMetrics, HausdorffNeedsAWall) {
    BlockGrid grid;
    add_lattice_block(grid,
                      {uniform_distances(1, 2), uniform_distances(1, 2), uniform_distances(1, 2)});
    const TriangleSurface uv = test::uv_sphere(Vec3::Zero(), 1.0, 8, 4);
    EXPECT_THROW(hausdorff_to_surface(grid, uv), std::invalid_argument);
}

// A wall of two quads, 1 x 1 and 2 x 2, side by side in the plane z = 0, and a surface whose
// vertices lie on it but for a spike over each quad: `small` above the small one's centre and
// 0.8 above the big one's (0.4 cells).
struct TwoSpikes {
    TriangleSurface wall, surface;
    explicit TwoSpikes(double small) {
        wall.points = {Vec3(0, 0, 0),    Vec3(1, 0, 0),    Vec3(1, 1, 0),   Vec3(0, 1, 0),
                       Vec3(1, -0.5, 0), Vec3(3, -0.5, 0), Vec3(3, 1.5, 0), Vec3(1, 1.5, 0)};
        wall.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
        surface.points = {Vec3(0.5, 0.5, small), Vec3(0.2, 0.2, 0), Vec3(0.8, 0.2, 0),
                          Vec3(2, 0.5, 0.8),     Vec3(1.5, 0, 0),   Vec3(2.5, 0, 0)};
        surface.triangles = {{0, 1, 2}, {3, 4, 5}};
    }
};

TEST(WallMetrics, SurfaceVerticesInWallCellsMeasureAFingerTheGridSkips) {
    // The small quad's spike 0.3 above it (0.3 cells).
    TwoSpikes spikes(0.3);
    const TriangleSurface& wall = spikes.wall;
    TriangleSurface& surface = spikes.surface;
    // 94 more vertices on the wall, in slivers along its edge y = 0: 100 in all.
    for (int k = 0; k < 47; ++k) {
        const int a = int(surface.points.size());
        surface.points.push_back(Vec3(0.02 * k, 0, 0));
        surface.points.push_back(Vec3(0.02 * k + 0.01, 0, 0));
        surface.triangles.push_back({a, a + 1, 1});
    }
    const HausdorffDistance h = hausdorff_to_surface(wall, surface);
    EXPECT_NEAR(h.surface_in_cells_max, 0.4, 1e-12);
    EXPECT_EQ(h.surface_in_cells_at, Vec3(2, 0.5, 0.8));  // the big quad's spike (0.4 cells)
    EXPECT_NEAR(h.surface_in_cells_distance, 0.8, 1e-12);
    EXPECT_NEAR(h.surface_to_grid, 0.8, 1e-12);
    // The 99th percentile of 100 vertices: the 99th smallest, the small quad's spike.
    EXPECT_NEAR(h.surface_in_cells_p99, 0.3, 1e-12);
}

// The worst vertex is the one farthest from the wall in wall cells, not in length: a spike of
// 0.45 over a unit quad (0.45 cells) beats one of 0.8 over a 2 x 2 quad (0.4 cells).
TEST(WallMetrics, TheWorstSurfaceVertexIsTheFarthestInWallCells) {
    const TwoSpikes spikes(0.45);
    const HausdorffDistance h = hausdorff_to_surface(spikes.wall, spikes.surface);
    EXPECT_NEAR(h.surface_in_cells_max, 0.45, 1e-12);
    EXPECT_EQ(h.surface_in_cells_at, Vec3(0.5, 0.5, 0.45));
    EXPECT_NEAR(h.surface_in_cells_distance, 0.45, 1e-12);
    EXPECT_NEAR(h.surface_to_grid, 0.8, 1e-12);  // the farthest in length is the other spike
}

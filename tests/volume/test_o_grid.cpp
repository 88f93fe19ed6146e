#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "grid_checks.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/validity.h"
#include "surface/analytic.h"
#include "surface/csg.h"
#include "surface/transform.h"
#include "volume/feature_snapping.h"
#include "volume/o_grid.h"
#include "volume/o_h_grid.h"
#include "volume/surface_placement.h"
#include "volume/wall_extrusion.h"
#include "volume/wall_lines.h"

using namespace hexmesh;

namespace {

constexpr double pi = 3.14159265358979323846;

// A sphere pushed in by a smooth bump: u = |x - c| - radius (1 - depth bump(x^)), x^ the
// direction from c. Dent: bump = exp(-(1 - x^.axis) / width), a pit around `axis`.
// Groove: bump = exp(-(x^.axis)^2 / width), a channel along the great circle normal to
// `axis`. Star-shaped around c (depth < 1), concave in the pit or channel.
class DentedSphere : public ImplicitFunction {
  public:
    enum Kind { dent, groove };
    DentedSphere(const Vec3& c, double radius, const Vec3& axis, double depth, double width,
                 Kind kind = dent)
        : c_(c),
          radius_(radius),
          axis_(axis.normalized()),
          depth_(depth),
          width_(width),
          kind_(kind) {}

    double value(const Vec3& p) const override {
        const Vec3 x = p - c_;
        return x.norm() - radius_ * (1 - depth_ * bump(x.normalized()));
    }
    Vec3 gradient(const Vec3& p) const override {
        const Vec3 x = p - c_;
        const double r = x.norm();
        const Vec3 e = x / r;
        const double a = e.dot(axis_);
        // gradient of bump over the direction, then d(direction)/dx = (I - e e^T) / r
        const Vec3 db = kind_ == dent ? Vec3(bump(e) / width_ * axis_)
                                      : Vec3(-2 * a / width_ * bump(e) * axis_);
        return e + radius_ * depth_ * (db - e.dot(db) * e) / r;
    }
    Box3 bounds() const override {
        return {c_ - Vec3::Constant(radius_), c_ + Vec3::Constant(radius_)};
    }

  private:
    double bump(const Vec3& e) const {
        const double a = e.dot(axis_);
        return std::exp(kind_ == dent ? -(1 - a) / width_ : -a * a / width_);
    }

    Vec3 c_;
    double radius_;
    Vec3 axis_;
    double depth_, width_;
    Kind kind_;
};

// Near-wall facts of the wall-normal lines (nodes k = 0, 1, ... of every block).
struct WallLines {
    double min_first = 1e300, max_first = 0;    // |x1 - x0|
    double min_growth = 1e300, max_growth = 0;  // |x2 - x1| / |x1 - x0|
    double max_law_error = 0;  // max over the law's layers m of ||x(m+1) - x(m)| / h q^m - 1|
    double max_angle_deg = 0;  // angle of x1 - x0 with grad u at x0
    double max_abs_u = 0;      // |u| at the wall nodes
};

WallLines measure_wall_lines(const BlockGrid& grid, const ImplicitFunction& body,
                             const WallLayers& law) {
    WallLines w;
    for (const Block& b : grid.blocks)
        for (int j = 0; j < b.nodes.nj; ++j)
            for (int i = 0; i < b.nodes.ni; ++i) {
                auto x = [&](int k) { return grid.points[b.node(i, j, k)]; };
                const double first = (x(1) - x(0)).norm();
                const double growth = (x(2) - x(1)).norm() / first;
                w.min_first = std::min(w.min_first, first);
                w.max_first = std::max(w.max_first, first);
                w.min_growth = std::min(w.min_growth, growth);
                w.max_growth = std::max(w.max_growth, growth);
                double height = law.first_height;
                for (int m = 0; m < law.layers; ++m, height *= law.growth_ratio) {
                    const double error = std::abs((x(m + 1) - x(m)).norm() / height - 1);
                    w.max_law_error = std::max(w.max_law_error, error);
                }
                // angle between unit vectors a, n: 2 asin(|a - n| / 2), accurate near 0
                const Vec3 a = (x(1) - x(0)).normalized(), n = body.gradient(x(0)).normalized();
                w.max_angle_deg =
                    std::max(w.max_angle_deg, 2 * std::asin((a - n).norm() / 2) * 180 / pi);
                w.max_abs_u = std::max(w.max_abs_u, std::abs(body.value(x(0))));
            }
    return w;
}

// The configuration of the quality figures: body size ~1, far field 10 away.
OGridOptions typical_options() {
    OGridOptions o;
    o.cells_per_edge = 16;
    o.layers = 24;
    o.wall_layers = {0.005, 1.15, 10};
    o.far_field_size = 10;
    return o;
}

// How far any node moves when `grid` (made with `o`) is built again from its own wall, as
// after the surface pass.
double moved_when_built_from_its_wall(const ImplicitFunction& body, const OGridOptions& o,
                                      const BlockGrid& grid) {
    OGridOptions again = o;
    again.wall_from = &grid.points;
    const BlockGrid rebuilt = make_o_grid(body, again);
    double moved = 0;
    for (size_t v = 0; v < grid.points.size(); ++v)
        moved = std::max(moved, (rebuilt.points[v] - grid.points[v]).norm());
    return moved;
}

// Runs f and expects std::invalid_argument whose message contains `words`.
template <class F>
void expect_invalid_argument(F&& f, const std::string& words) {
    try {
        f();
        ADD_FAILURE() << "no exception, expected one mentioning '" << words << "'";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(OGrid, SixRightHandedBlocksShareTheirInterfaceNodes) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 0.5);
    OGridOptions o = typical_options();
    o.cells_per_edge = 6;
    o.layers = 14;
    const BlockGrid grid = make_o_grid(sphere, o);
    const int n = o.cells_per_edge, nk = o.layers;
    const Id patch_nodes = 6 * Id(n) * n + 2;  // unique nodes of the 6 patches
    const char* names[] = {"shell_xmin", "shell_xmax", "shell_ymin",
                           "shell_ymax", "shell_zmin", "shell_zmax"};
    ASSERT_EQ(grid.blocks.size(), 6u);
    for (int b = 0; b < 6; ++b) {
        const Block& block = grid.blocks[b];
        EXPECT_EQ(block.name, names[b]);
        EXPECT_EQ(block.nodes.ni, n + 1);
        EXPECT_EQ(block.nodes.nj, n + 1);
        EXPECT_EQ(block.nodes.nk, nk + 1);
        EXPECT_EQ(block.face_patch[kmin], "wall");
        EXPECT_EQ(block.face_patch[kmax], "farfield");
        for (BlockFace f : {imin, imax, jmin, jmax}) EXPECT_EQ(block.face_patch[f], "");
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                EXPECT_EQ(grid.kinds[block.node(i, j, 0)], VertexKind::slip);
                EXPECT_EQ(grid.kinds[block.node(i, j, nk / 2)], VertexKind::interior);
                EXPECT_EQ(grid.kinds[block.node(i, j, nk)], VertexKind::fixed);
                EXPECT_EQ(block.node(i, j, nk) - block.node(i, j, 0), nk * patch_nodes);
            }
    }
    EXPECT_EQ(Id(grid.points.size()), patch_nodes * (nk + 1));
    EXPECT_EQ(std::count(grid.kinds.begin(), grid.kinds.end(), VertexKind::slip), patch_nodes);
    EXPECT_EQ(std::count(grid.kinds.begin(), grid.kinds.end(), VertexKind::fixed), patch_nodes);
    EXPECT_EQ(grid.num_cells(), 6 * Id(n) * n * nk);
    // Conforming interfaces: the faces used once are the wall and the far field, n^2 per block.
    const auto faces = test_support::count_faces(to_hex_mesh(grid));
    EXPECT_EQ(faces.boundary, 2 * 6 * Id(n) * n);
    EXPECT_EQ(faces.over_shared, 0);
    // Right-handed: every corner tet of every cell positive (exact predicate).
    EXPECT_EQ(count_inversions(to_hex_mesh(grid)).corner_tets, 0);
}

TEST(OGrid, SphereWallAndFarFieldNodesLieOnTheirSurfaces) {
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 0.5);
    const OGridOptions o = typical_options();
    const BlockGrid grid = make_o_grid(sphere, o);
    const double h = grid_length_scale(sphere, o.cells_per_edge);
    for (size_t v = 0; v < grid.points.size(); ++v) {
        const double r = (grid.points[v] - c).norm();
        if (grid.kinds[v] == VertexKind::slip)
            EXPECT_LT(std::abs(sphere.value(grid.points[v])), 1e-8 * h);
        else if (grid.kinds[v] == VertexKind::fixed)
            EXPECT_NEAR(r, 10.0, 1e-12 * 10);
        else
            EXPECT_TRUE(r > 0.5 && r < 10) << r;
    }
}

TEST(OGrid, SphereLinesFollowTheLawAndLeaveTheWallOrthogonally) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 0.5);
    const OGridOptions o = typical_options();
    const WallLayers& law = o.wall_layers;
    const WallLines w = measure_wall_lines(make_o_grid(sphere, o), sphere, law);
    EXPECT_NEAR(w.min_first, law.first_height, 1e-9 * law.first_height);
    EXPECT_NEAR(w.max_first, law.first_height, 1e-9 * law.first_height);
    EXPECT_NEAR(w.min_growth, law.growth_ratio, 1e-9);
    EXPECT_NEAR(w.max_growth, law.growth_ratio, 1e-9);
    EXPECT_LT(w.max_law_error, 1e-9);  // all 10 layers
    EXPECT_LT(w.max_angle_deg, 0.5);
}

TEST(OGrid, LinesAreBuiltFromAGivenWallGrid) {
    // Wall nodes moved along the sphere (a rotation about the centre by 0.05 rad): the grid
    // made from them keeps them exactly, and its lines follow the law and leave the wall
    // orthogonally from their new places.
    const Vec3 c(0.1, -0.2, 0.3);
    const Sphere sphere(c, 0.5);
    OGridOptions o = typical_options();
    BlockGrid moved = make_o_grid(sphere, o);
    const Mat3 turn = Eigen::AngleAxisd(0.05, Vec3(1, 2, 2).normalized()).toRotationMatrix();
    for (size_t v = 0; v < moved.points.size(); ++v)
        if (moved.kinds[v] == VertexKind::slip) moved.points[v] = c + turn * (moved.points[v] - c);
    o.wall_from = &moved.points;
    const BlockGrid grid = make_o_grid(sphere, o);
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::slip) {
            EXPECT_EQ(grid.points[v], moved.points[v]);
        }
    const WallLines w = measure_wall_lines(grid, sphere, o.wall_layers);
    EXPECT_LT(w.max_law_error, 1e-9);
    EXPECT_LT(w.max_angle_deg, 0.5);
    EXPECT_EQ(count_inversions(to_hex_mesh(grid)).corner_tets, 0);
    // Points of a grid made with other options are refused.
    const std::vector<Vec3> fewer(moved.points.begin(), moved.points.end() - 1);
    o.wall_from = &fewer;
    expect_invalid_argument([&] { make_o_grid(sphere, o); }, "wall_from");
}

TEST(OGrid, SphereShellIsValid) {
    const Sphere sphere(Vec3::Zero(), 0.5);
    const QualityReport q = measure_quality(to_hex_mesh(make_o_grid(sphere, typical_options())));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, 0.8);  // the patch corners: 3 cells at ~120 degrees
}

// The shell of typical_options() around `body`: valid, min SJ above `min_sj`, wall on u = 0,
// and the boundary layer's heights are the law's on every line, bent or not, leaving the
// wall orthogonally.
void expect_valid_shell_on_the_law(const ImplicitFunction& body, double min_sj) {
    const OGridOptions o = typical_options();
    const BlockGrid grid = make_o_grid(body, o);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, min_sj);
    const WallLines w = measure_wall_lines(grid, body, o.wall_layers);
    EXPECT_LT(w.max_abs_u, 1e-8 * grid_length_scale(body, o.cells_per_edge));
    // Bent lines too: the cell heights of the boundary layer are the law's.
    EXPECT_NEAR(w.min_first, 0.005, 1e-9 * 0.005);
    EXPECT_NEAR(w.max_first, 0.005, 1e-9 * 0.005);
    EXPECT_LT(w.max_law_error, 1e-9);
    EXPECT_LT(w.max_angle_deg, 0.5);
}

TEST(OGrid, EllipsoidShellIsValidAndOrthogonalAtTheWall) {
    const Ellipsoid body(Vec3(0.1, 0, 0), Vec3(0.6, 0.4, 0.2));
    expect_valid_shell_on_the_law(body, 0.4);
}

TEST(OGrid, DentedBodyShellIsValidAndOrthogonalAtTheWall) {
    const DentedSphere body(Vec3::Zero(), 0.5, Vec3(1, 0.3, 0.2), 0.3, 0.15);
    // The dent is concave: the chord between two of its points 53 degrees apart passes more
    // than the boundary layer's first 4 heights outside the body.
    const Vec3 axis = Vec3(1, 0.3, 0.2).normalized(), side = Vec3(-0.3, 1, 0).normalized();
    const Vec3 a = place_on_surface(body, Vec3::Zero(), axis + 0.5 * side, 1e-3);
    const Vec3 b = place_on_surface(body, Vec3::Zero(), axis - 0.5 * side, 1e-3);
    ASSERT_GT(body.value(0.5 * (a + b)), 0.02);

    expect_valid_shell_on_the_law(body, 0.6);
}

TEST(OGrid, GroovedBodyShellIsValid) {
    // A narrow channel running diagonally to the patch lattice: normals converge within
    // 0.05 of the wall, well inside the far field's distance.
    const DentedSphere body(Vec3::Zero(), 0.5, Vec3(1, 1, 1), 0.2, 0.05, DentedSphere::groove);
    for (int n : {8, 16, 32}) {
        OGridOptions o = typical_options();
        o.cells_per_edge = n;
        const BlockGrid grid = make_o_grid(body, o);
        const QualityReport q = measure_quality(to_hex_mesh(grid));
        EXPECT_EQ(q.inverted_corner_tets, 0) << "n = " << n;
        EXPECT_GT(q.min_scaled_jacobian, 0.1) << "n = " << n;
        const WallLines w = measure_wall_lines(grid, body, o.wall_layers);
        EXPECT_LT(w.max_law_error, 1e-9) << "n = " << n;
        // The lines in the groove turn within about its focal distance: their first edge is
        // up to 0.87 degrees off the normal (the laid layers then take the normal itself).
        EXPECT_LT(w.max_angle_deg, 1.0) << "n = " << n;
    }
}

TEST(OGrid, BoxShellLeavesItsCreasesOnTheFacesOffsetPlanes) {
    // A 4 x 2 x 1 box: its patch edges run along the box's edges. The lines from those wall
    // nodes leave along the bisector of the faces meeting there, their layer nodes at the
    // law's distances from every such face (sqrt(2), sqrt(3) times further along the line),
    // so laying the layers again hardly moves anything; with lines along one face's normal (as
    // grad u has it there) the grid had cells of scaled Jacobian 0.0015 after optimization.
    // The lines turn towards the far field within half the box's diagonal, the lines next to
    // the corners sharply: the grid is valid, but cells there are thin (0.004) until the
    // optimizer evens them out.
    const Vec3 c(0.3, -0.1, 0.2);
    const Box box(c, Vec3(1.0, 0.5, 0.25));
    const OGridOptions o = typical_options();
    BlockGrid grid = make_o_grid(box, o);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, 0);
    const double h = grid_length_scale(box, o.cells_per_edge);
    int creases = 0, corners = 0;
    double worst = 0;  // relative error of a layer node's distance to a face's plane
    for (const WallFace& f : wall_faces(grid))
        for (int jq = 0; jq < f.nq; ++jq)
            for (int ip = 0; ip < f.np; ++ip) {
                const Vec3 x0 = grid.points[f.node(ip, jq, 0)];
                std::vector<Vec3> normals;
                append_wall_normals(box, x0, 1.0, 1e-9 * h, normals);
                creases += normals.size() == 2;
                corners += normals.size() == 3;
                double height = 0, step = o.wall_layers.first_height;
                for (int m = 1; m <= o.wall_layers.layers;
                     ++m, step *= o.wall_layers.growth_ratio) {
                    height += step;
                    for (const Vec3& n : normals)
                        worst = std::max(
                            worst,
                            std::abs((grid.points[f.node(ip, jq, m)] - x0).dot(n) / height - 1));
                }
            }
    // Every patch edge node of the 6 blocks' walls (each counted once per block it is in).
    EXPECT_EQ(creases, 6 * 4 * 15);
    EXPECT_EQ(corners, 6 * 4);
    // To O(b): the lines start turning towards the far field at once (5e-3 measured).
    EXPECT_LT(worst, 1e-2);
    const std::vector<Vec3> built = grid.points;
    extrude_wall_layers(grid, box, o.wall_layers);
    double moved = 0;
    for (size_t v = 0; v < built.size(); ++v)
        moved = std::max(moved, (grid.points[v] - built[v]).norm());
    EXPECT_LT(moved, 0.05 * h);  // 0.022 h measured; a line along one face's normal: ~0.5 h
}

// Wall nodes of `grid` on the first and last rows of every block's wall at a crease (two or
// more faces of `body` within 1e-9 h) and at a corner (three).
std::pair<int, int> patch_edge_nodes_on_features(const BlockGrid& grid,
                                                 const ImplicitFunction& body, double h) {
    int creases = 0, corners = 0;
    for (const WallFace& f : wall_faces(grid))
        for (int q : {0, f.nq - 1})
            for (int p = 0; p < f.np; ++p) {
                std::vector<Vec3> normals;
                append_wall_normals(body, grid.points[f.node(p, q, 0)], 1.0, 1e-9 * h, normals);
                creases += normals.size() >= 2;
                corners += normals.size() == 3;
            }
    return {creases, corners};
}

TEST(OGrid, TurnedBoxGetsThePatchCornersOnItsCorners) {
    // A 4 x 2 x 1 box turned 15 degrees about z still has one corner in each octant; turned 45
    // degrees about z, or 37 about (1, 2, 3), two corners share an octant and the octants are
    // those of the box's own axes. Either way the rays span its corners, so the 8 patch-corner
    // nodes sit on them and every patch-edge node on an edge, and the far field turns with
    // them. Through the bounds' box the patch corners missed the box's corners and the
    // pipeline's grid kept 5 % of its first layer on target (20 degrees), or had inverted
    // cells (45 degrees).
    // Also a cube turned 60 degrees about (1, 1, 1): one corner in each octant, but octants 0
    // and 1 hold the two ends of a face diagonal; taken so, the patches would fold.
    struct Turned {
        Vec3 half, axis;
        double degrees;
    };
    for (const Turned& t : {Turned{Vec3(1.0, 0.5, 0.25), Vec3::UnitZ(), 15.0},
                            Turned{Vec3(1.0, 0.5, 0.25), Vec3::UnitZ(), 45.0},
                            Turned{Vec3(1.0, 0.5, 0.25), Vec3(1, 2, 3), 37.0},
                            Turned{Vec3(0.5, 0.5, 0.5), Vec3(1, 1, 1), 60.0}}) {
        SCOPED_TRACE(t.degrees);
        const Mat3 turn = rotation_from_axis_angle(t.axis, t.degrees);
        const Body box = std::make_shared<Transformed>(std::make_shared<Box>(Vec3::Zero(), t.half),
                                                       Vec3(0.1, 0.2, -0.1), turn);
        const OGridOptions o = typical_options();
        const BlockGrid grid = make_o_grid(*box, o);
        const double h = grid_length_scale(*box, o.cells_per_edge);
        const auto [creases, corners] = patch_edge_nodes_on_features(grid, *box, h);
        EXPECT_EQ(creases, 6 * 2 * 17);  // rows q = 0 and n of every block's wall
        EXPECT_EQ(corners, 6 * 4);
        // The far-field sphere's patches are turned with them: the far node of the lattice
        // corner (n, n, n) lies on one of the turned box's diagonal directions.
        const Vec3 centre = box->bounds().center();
        const Id far_corner = Id(grid.points.size()) - 1;  // last node of the last layer
        const Vec3 along = turn.transpose() * (grid.points[far_corner] - centre) / o.far_field_size;
        EXPECT_LT((along.cwiseAbs() - Vec3::Constant(1 / std::sqrt(3.0))).norm(), 1e-9) << along;
        // Built again from its own wall (as after the surface pass), it is the same grid: the
        // patch corners and the far field's turn are read back from the wall's corner nodes.
        EXPECT_LT(moved_when_built_from_its_wall(*box, o, grid), 1e-9 * o.far_field_size);
        OGridOptions bounds_box = o;
        bounds_box.patch_corners_on_body_corners = false;
        if (t.degrees != 60) {  // the cube's turned corners lie on its bounds' diagonals
            EXPECT_EQ(patch_edge_nodes_on_features(make_o_grid(*box, bounds_box), *box, h).second,
                      0);
        }
    }
}

// A flat cross (two bars 1 x 0.2 x 0.2 crossing at the centre) has 24 corners: in each octant
// two convex ones at the ends of its arms and the inner one where the arms meet. Through the
// bounds' box the 8 patch corners land on the 4 inner vertical edges (a ball round each more
// than 0.6 inside the body), where one of the three wall cells around each folds round the
// edge. The rays instead span the 8 ends of one bar: every patch corner on a convex corner of
// the body, and every patch edge on its surface (along the bar's edges), which the 8 corners
// turning the same way round in every quadrant (a box turned about z) are not: those edges
// cut across the air between the arms. Built again from its own wall, the grid keeps them.
TEST(OGrid, CrossGetsThePatchCornersOnConvexCorners) {
    const Body cross = std::make_shared<Csg>(
        CsgOp::Union, std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(0.5, 0.1, 0.1)),
                                        std::make_shared<Box>(Vec3::Zero(), Vec3(0.1, 0.5, 0.1))});
    const OGridOptions o = typical_options();
    const int n = o.cells_per_edge;
    const double h = grid_length_scale(*cross, n);
    const auto patch_corner = [&](const BlockGrid& grid, int c) {
        // lattice corner c of the wall: block zmin (c < 4) or zmax, node (i, j) at its ends
        const Block& b = grid.blocks[c & 4 ? 5 : 4];
        for (int j : {0, n})
            for (int i : {0, n}) {
                const Vec3& x = grid.points[b.node(i, j, 0)];
                if ((x.x() > 0) == bool(c & 1) && (x.y() > 0) == bool(c & 2)) return x;
            }
        return Vec3(Vec3::Constant(std::nan("")));
    };
    OGridOptions bounds_box = o;
    bounds_box.patch_corners_on_body_corners = false;
    const BlockGrid through_bounds = make_o_grid(*cross, bounds_box);
    const BlockGrid grid = make_o_grid(*cross, o);
    const bool x_bar = std::abs(patch_corner(grid, 0).x()) > std::abs(patch_corner(grid, 0).y());
    for (int c = 0; c < 8; ++c) {
        SCOPED_TRACE(c);
        EXPECT_GT(inside_share(*cross, patch_corner(through_bounds, c), 0.5 * h), 0.6);
        const Vec3 x = patch_corner(grid, c);
        EXPECT_LT((x.cwiseAbs() - (x_bar ? Vec3(0.5, 0.1, 0.1) : Vec3(0.1, 0.5, 0.1))).norm(),
                  1e-12)
            << x.transpose();
        EXPECT_LT(inside_share(*cross, x, 0.25 * h), 0.2);
    }
    EXPECT_LT(moved_when_built_from_its_wall(*cross, o, grid), 1e-9 * o.far_field_size);
}

TEST(OGrid, BoxFarFieldNodesLieOnTheBoxFaces) {
    const Vec3 c(1, 2, 3);
    const Ellipsoid body(c, Vec3(0.6, 0.4, 0.2));
    OGridOptions o = typical_options();
    o.far_field = FarFieldShape::box;
    o.far_field_size = 2;
    const BlockGrid grid = make_o_grid(body, o);
    const int n = o.cells_per_edge, nk = o.layers;
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        // Block b's far-field face lies on the box face of cube patch b.
        const int axis = int(b) / 2;
        const double side = b % 2 ? 2.0 : -2.0;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const Vec3 x = grid.points[grid.blocks[b].node(i, j, nk)] - c;
                EXPECT_EQ(x[axis], side);
                EXPECT_LE(x.cwiseAbs().maxCoeff(), 2.0);
            }
    }
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.min_scaled_jacobian, 0.25);
}

TEST(OGrid, FarFieldSphereIsCentredOnTheGivenCentre) {
    const Sphere sphere(Vec3::Zero(), 0.5);
    OGridOptions o = typical_options();
    o.cells_per_edge = 6;
    o.centre = Vec3(0.2, -0.1, 0.05);
    const BlockGrid grid = make_o_grid(sphere, o);
    for (size_t v = 0; v < grid.points.size(); ++v)
        if (grid.kinds[v] == VertexKind::fixed) {
            EXPECT_NEAR((grid.points[v] - *o.centre).norm(), 10.0, 1e-12 * 10);
        }
    EXPECT_EQ(count_inversions(to_hex_mesh(grid)).corner_tets, 0);
}

TEST(OGrid, RefusesBadOptions) {
    const Sphere sphere(Vec3::Zero(), 0.5);  // bounds corners at 0.866 from the centre
    auto with = [](auto change) {
        OGridOptions o = typical_options();
        change(o);
        return o;
    };
    expect_invalid_argument(
        [&] { make_o_grid(sphere, with([](OGridOptions& o) { o.far_field_size = 0.8; })); },
        "far-field sphere radius 0.8 does not enclose the body's bounds");
    expect_invalid_argument(
        [&] {
            make_o_grid(sphere, with([](OGridOptions& o) {
                            o.far_field = FarFieldShape::box;
                            o.far_field_size = 0.55;
                        }));
        },
        "far-field box half-size 0.55 does not enclose the body's bounds");
    expect_invalid_argument(
        [&] { make_o_grid(sphere, with([](OGridOptions& o) { o.cells_per_edge = 1; })); },
        "cells_per_edge");
    expect_invalid_argument(
        [&] { make_o_grid(sphere, with([](OGridOptions& o) { o.layers = 0; })); }, "layers");
    expect_invalid_argument(
        [&] { make_o_grid(sphere, with([](OGridOptions& o) { o.layers = 10; })); },
        "wall_layers has 10 layers but the lines have only 10 cells");
    expect_invalid_argument(
        [&] {
            make_o_grid(sphere, with([](OGridOptions& o) { o.wall_layers = {6.0, 1.2, 10}; }));
        },
        "does not fit the wall-normal line of ");
    expect_invalid_argument(
        [&] {
            make_o_grid(sphere, with([](OGridOptions& o) { o.wall_layers = {0.0, 1.2, 10}; }));
        },
        "first height");
    const Torus torus(Vec3::Zero(), 1.0, 0.3);  // its bounds' centre is in the hole
    expect_invalid_argument([&] { make_o_grid(torus, typical_options()); },
                            "is not inside the body");
}

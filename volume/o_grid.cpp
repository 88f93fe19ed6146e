// make_o_grid: the wall nodes and their rays, the lines from the wall to the far field and
// their nodes (along bent wall-normal lines, or along continuation paths), the six shell blocks.
#include "volume/o_grid.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "surface/implicit_features.h"
#include "volume/cube_sphere.h"
#include "volume/feature_snapping.h"
#include "volume/o_h_grid.h"
#include "volume/path_lines.h"
#include "volume/surface_placement.h"
#include "volume/wall_lines.h"
#include "volume/wall_normal_lines.h"

namespace hexmesh {
namespace {

// The far field must keep this fraction of the bounds diagonal between itself and the bounds.
constexpr double far_field_margin = 0.1;

void check_options(const OGridOptions& o) {
    if (o.cells_per_edge < 2)
        throw std::invalid_argument(
            fmt::format("cells_per_edge is {}: it must be at least 2", o.cells_per_edge));
    if (o.layers < 1)
        throw std::invalid_argument(fmt::format("layers is {}: it must be at least 1", o.layers));
    const WallLayers& law = o.wall_layers;
    if (law.layers < 0 || (law.layers > 0 && !(law.first_height > 0 && law.growth_ratio > 0)))
        throw std::invalid_argument(fmt::format(
            "wall_layers (first height {}, growth ratio {}, {} layers): the number of layers "
            "must be >= 0, and with layers the first height and growth ratio must be > 0",
            law.first_height, law.growth_ratio, law.layers));
    if (law.layers >= o.layers)
        throw std::invalid_argument(fmt::format(
            "wall_layers has {} layers but the lines have only {} cells (layers): the boundary "
            "layer needs at least one cell beyond it to reach the far field; use fewer wall "
            "layers or more cells",
            law.layers, o.layers));
    if (o.paths && o.layers < 2)
        throw std::invalid_argument(fmt::format(
            "layers is {}: lines along paths need at least 2 cells, one to the far surface and "
            "one beyond it to the far field",
            o.layers));
}

// Throws unless the far field encloses the bounds with the margin.
void check_far_field(const Box3& box, const Vec3& centre, const OGridOptions& o) {
    double reach = 0;  // distance (sphere) or max-norm distance (box) of the farthest corner
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner((c & 1 ? box.hi : box.lo).x(), (c & 2 ? box.hi : box.lo).y(),
                          (c & 4 ? box.hi : box.lo).z());
        const Vec3 r = corner - centre;
        reach = std::max(reach,
                         o.far_field == FarFieldShape::sphere ? r.norm() : r.cwiseAbs().maxCoeff());
    }
    const double needed = reach + far_field_margin * box.diagonal();
    if (!(o.far_field_size >= needed)) {
        const bool sphere = o.far_field == FarFieldShape::sphere;
        throw std::invalid_argument(fmt::format(
            "far-field {} {} {:.6g} does not enclose the body's bounds with margin: it must "
            "be at least {:.6g} ({:.6g} from the centre to the farthest bounds corner plus "
            "{} bounds diagonal)",
            sphere ? "sphere" : "box", sphere ? "radius" : "half-size", o.far_field_size, needed,
            reach, far_field_margin));
    }
}

// The rotation nearest the affine map that sends the cube's corners (+-1, +-1, +-1) closest
// to `corners` (least squares): the orthogonal factor of its polar decomposition. The
// identity for an axis-aligned box; a turned box's turn.
Mat3 corners_rotation(const CubeCorners& corners) {
    Mat3 a = Mat3::Zero();  // sum of c s^T / 8: the least-squares map, as sum of s s^T = 8 I
    for (int c = 0; c < 8; ++c)
        a += corners[c] * Vec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1).transpose() / 8;
    const Eigen::JacobiSVD<Mat3> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0) u.col(2) *= -1;
    return u * svd.matrixV().transpose();
}

// The six shell blocks over the node array of make_o_grid: the node of surface point s on
// layer k has id k ns + s.
BlockGrid finish_o_grid(BlockGrid grid, const CubeSurfaceLattice& surface, int n, int nk) {
    const Id ns = surface.size();
    for (const CubePatch& patch : cube_patches) {
        Block b{std::string("shell_") + patch.side, {n + 1, n + 1, nk + 1}, {}, {}};
        b.face_patch[kmin] = "wall";
        b.face_patch[kmax] = "farfield";
        b.node_ids.resize(b.nodes.count());
        for (int k = 0; k <= nk; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i)
                    b.node_ids[b.nodes.flat(i, j, k)] =
                        k * ns + surface.number_of(surface.patch_point(patch, i, j));
        grid.blocks.push_back(std::move(b));
    }
    return grid;
}

// The rays of make_o_grid through the lattice points: through the bounds' box, or (box-like
// bodies) through the body's corners, so the patch edges run along its edges.
struct LatticeRays {
    int n;
    Vec3 half;
    std::optional<CubeCorners> corners;

    Vec3 operator()(const LatticePoint& p) const {
        return corners ? cube_sphere_ray(p, n, *corners) : cube_sphere_ray(p, n, half);
    }
};

// The wall nodes: given, or the radial projections of the rays through the bounds' box, then
// (box-like bodies: body_corners_by_octant; or 8 of the body's convex corners spanning a box
// whose edges lie on it: convex_corners_by_octant) through the body's corners, which `ray`
// takes.
std::vector<Vec3> place_o_wall(const ImplicitFunction& body, const OGridOptions& options,
                               const CubeSurfaceLattice& surface, const Vec3& centre, double h,
                               LatticeRays& ray) {
    const int n = options.cells_per_edge;
    const WallPaths* paths = options.paths;
    const Id ns = surface.size();
    std::vector<Vec3> wall(ns);
    const auto place_wall = [&] {
        tbb::parallel_for(Id(0), ns, [&](Id s) {
            wall[s] = options.wall_from ? (*options.wall_from)[s]
                      : paths           ? paths->wall(s)
                                        : place_on_surface(body, centre, ray(surface.points[s]), h);
        });
    };
    place_wall();
    if (paths) {
        // The continuation's patches follow no corner of the body.
    } else if (options.patch_corners_on_body_corners && !options.wall_from) {
        const std::vector<Vec3> found = body_corners_near(body, wall, h);
        ray.corners = body_corners_by_octant(centre, found, h);
        if (!ray.corners) ray.corners = convex_corners_by_octant(body, centre, found, h);
        if (ray.corners) place_wall();
    } else if (options.patch_corners_on_body_corners) {
        // A given wall keeps the choice of the grid it came from: its 8 patch-corner nodes sit
        // on body corners exactly when that grid's rays spanned them, and they are those.
        std::array<Vec3, 8> at;
        for (int c = 0; c < 8; ++c)
            at[c] = wall[surface.number_of({c & 1 ? n : 0, c & 2 ? n : 0, c & 4 ? n : 0})];
        ray.corners = corners_at_patch_corners(body, centre, at, h);
    }
    return wall;
}

// How each line leaves the wall and where it ends: the wall node's unit normal and reach (the
// length of its unit_offset, 1 on a smooth wall), and its far-field node.
void aim_lines(const ImplicitFunction& body, const OGridOptions& options,
               const CubeSurfaceLattice& surface, const LatticeRays& ray, const Vec3& centre,
               double h, const std::vector<Vec3>& wall, std::vector<Vec3>& normal,
               std::vector<double>& reach, std::vector<Vec3>& far) {
    const int n = options.cells_per_edge;
    const WallPaths* paths = options.paths;
    const Mat3 turn = ray.corners ? corners_rotation(*ray.corners) : Mat3::Identity();
    tbb::parallel_for(Id(0), surface.size(), [&](Id s) {
        const LatticePoint& p = surface.points[s];
        const Vec3 dir = ray(p);
        // At a crease or corner the line leaves along the bisector of the faces meeting there
        // (the direction the boundary layer is laid along), not along one face's normal.
        const std::optional<Vec3> offset = unit_offset(body, wall[s], 1.0, 1e-6 * h);
        const Vec3 g = offset ? *offset : body.gradient(wall[s]);
        normal[s] = g.norm() > 0 ? Vec3(g.normalized()) : Vec3(dir.normalized());
        reach[s] = offset ? offset->norm() : 1.0;
        // The far field's nodes: the cube sphere of the unit cube, whatever the body's
        // proportions (a cube sphere stretched like the body has cells squeezed flat on a
        // sphere: min scaled Jacobian 0.05 there round a 4 x 2 x 1 box), turned like the
        // patches on a turned body's corners (a far-field box keeps its axes).
        // With paths: radially out from each path's end (the far surface is star-shaped around
        // the centre), where the lattice point's direction has no bearing.
        const Vec3 q = !paths                          ? cube_sphere_ray(p, n, Vec3::Ones())
                       : paths->far_directions.empty() ? Vec3(paths->outer(s) - centre)
                                                       : paths->far_directions[s];
        far[s] = centre + options.far_field_size * (options.far_field == FarFieldShape::sphere
                                                        ? Vec3(turn * q / q.norm())
                                                        : Vec3(q / q.cwiseAbs().maxCoeff()));
    });
}

}  // namespace

BlockGrid make_o_grid(const ImplicitFunction& body, const OGridOptions& options) {
    check_options(options);
    const int n = options.cells_per_edge, nk = options.layers;
    const Box3 box = body.bounds();
    const WallPaths* paths = options.paths;
    if (paths && (paths->cells_per_edge != n || paths->lines.empty()))
        throw std::invalid_argument("paths: a wall lattice made with other options");
    const Vec3 centre = paths ? paths->centre : options.centre.value_or(box.center());
    const double h = grid_length_scale(body, n);
    if (!paths)
        require_inside(body, centre);  // a continuation's centre needs only see its first level
    check_far_field(box, centre, options);

    const CubeSurfaceLattice surface = make_cube_surface_lattice(n);
    const Id ns = surface.size();
    if (options.wall_from && Id(options.wall_from->size()) != (nk + 1) * ns)
        throw std::invalid_argument("wall_from: the points of a grid made with other options");
    LatticeRays ray{n, 0.5 * box.size(), std::nullopt};
    const std::vector<Vec3> wall = place_o_wall(body, options, surface, centre, h, ray);
    std::vector<Vec3> normal(ns), far(ns);
    std::vector<double> reach(ns);
    aim_lines(body, options, surface, ray, centre, h, wall, normal, reach, far);

    BlockGrid grid;
    grid.points.assign((nk + 1) * ns, Vec3::Zero());
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    const auto set_line = [&](Id s, const std::vector<Vec3>& x) {
        for (int k = 1; k < nk; ++k) grid.points[k * ns + s] = x[k];
        grid.points[s] = wall[s];
        grid.points[nk * ns + s] = far[s];
        grid.kinds[s] = VertexKind::slip;
        grid.kinds[nk * ns + s] = VertexKind::fixed;
    };
    if (paths)
        place_nodes_on_paths(*paths, wall, far, nk, options.wall_layers, set_line);
    else
        place_nodes_on_lines(surface, wall, normal, reach, far, box.diagonal(), nk,
                             options.wall_layers, set_line);
    return finish_o_grid(std::move(grid), surface, n, nk);
}

}  // namespace hexmesh

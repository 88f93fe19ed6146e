#include "volume/o_grid.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <stdexcept>
#include <string>

#include "surface/implicit_features.h"
#include "volume/cube_sphere.h"
#include "volume/feature_snapping.h"
#include "volume/o_h_grid.h"
#include "volume/surface_placement.h"
#include "volume/wall_lines.h"

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

// Smooth ramp from 0 to 1 on [0, 1] with zero slope at both ends.
double smoothstep(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

// Lines leaving a concave wall along its normals converge at the focal distance rho. Along
// x(tau) = w + tau m(tau), m turning from the normal to the straight direction with the ramp
// b = smoothstep(tau / bend), the normal part shrinks the spacing of neighbouring lines by
// the factor 1 - tau (1 - b) / rho >= 1 - 0.26 bend / rho: bend = 2 rho keeps half of it.
constexpr double bend_per_focal_distance = 2.0;
// How fast the bend length may grow along the wall away from a concave part (length per
// length): a bounded slope keeps neighbouring lines bending alike.
constexpr double bend_slope = 0.25;
// Round a body with creases, every line has turned to its straight direction within this
// fraction of the body's bounds diagonal from the wall, so the lines of a flat face fan out
// as soon as those of its edges
// (which leave along the bisector, 45 degrees out): with the turn spread over the whole line,
// the cells beside a 4 x 2 x 1 box's edge lines were 10 times wider than their neighbours
// half-way to the far field (volume ratio 22), and the grid's refinement inverted there.
constexpr double max_bend_per_diagonal = 0.5;

// A wall-normal line x(tau) = wall + tau r(tau) m(tau), tau in [0, length], m the unit blend
// of the wall normal and the straight direction to the far-field node (ramp b =
// smoothstep(tau / bend)) and r = (1 - b) reach + b: x(0) = wall, x(length) = far. At a
// smooth wall reach is 1 and tau the distance from the wall node; at a crease or corner the
// normal is the bisector of the faces meeting there and reach its length in unit_offset
// (volume/wall_lines.h), so that near the wall x(tau) lies at distance tau from every face's
// plane, where the boundary layer is laid; the line turns round as it leaves.
struct WallNormalLine {
    Vec3 wall, normal, straight;
    double length, bend, reach;

    double b(double tau) const { return smoothstep(tau / bend); }
    // The length in the law of a unit length of line at tau: chords are reach times longer
    // than the law's heights at the wall, as long as them where the line has turned.
    double speed(double tau) const { return (1 - b(tau)) * reach + b(tau); }
    Vec3 at(double tau) const {
        const double ramp = b(tau);
        const Vec3 m = (1 - ramp) * normal + ramp * straight;
        // m vanishes only for a normal pointing straight back to the body: go straight.
        const double norm = m.norm();
        return wall + tau * speed(tau) * (norm > 1e-6 ? Vec3(m / norm) : straight);
    }
};

// The nk+1 nodes of a line: the chord |x(k) - x(k-1)| is (a(k) - a(k-1)) speed for every cell
// but the last, a = wall_distances(L, nk, law), L the length of the line in the law (its arc
// length with each piece divided by the speed there, the arc length on a smooth wall), so the
// law holds exactly for the cell heights of the bent line too; the last cell ends on the
// far-field node and takes up the difference between chords and arc (small: the line bends
// gently there). L is summed over chords of the line sampled 16 times finer than the nodes.
void place_nodes(const WallNormalLine& line, int nk, const WallLayers& law, std::vector<Vec3>& x) {
    constexpr int refine = 16;
    const std::vector<double> d = wall_distances(line.length, nk, law);
    double arc = 0;
    Vec3 previous = line.wall;
    double previous_tau = 0;
    for (int k = 0; k < nk; ++k)
        for (int r = 1; r <= refine; ++r) {
            const double tau = d[k] + (d[k + 1] - d[k]) * r / refine;
            const Vec3 p = line.at(tau);
            arc += (p - previous).norm() / line.speed(0.5 * (tau + previous_tau));
            previous = p;
            previous_tau = tau;
        }
    const std::vector<double> a = wall_distances(arc, nk, law);

    x.assign(nk + 1, line.wall);
    double tau = 0;
    for (int k = 1; k < nk; ++k) {
        // The first tau beyond the previous node at the wanted chord: bracket, then regula
        // falsi (Illinois variant), which converges in a few steps on these nearly straight
        // pieces.
        const double height = a[k] - a[k - 1];
        auto excess = [&](double t) {
            return (line.at(t) - x[k - 1]).norm() - height * line.speed(0.5 * (t + tau));
        };
        const double tolerance = 1e-14 * height;
        double lo = tau, hi = std::min(tau + height, line.length);
        double f_lo = excess(lo), f_hi = excess(hi);
        while (f_hi < 0 && hi < line.length) {
            lo = hi, f_lo = f_hi;
            hi = std::min(tau + 2 * (hi - tau), line.length);
            f_hi = excess(hi);
        }
        double t = hi, f = f_hi, g_lo = f_lo, g_hi = f_hi;  // g: Illinois-scaled f at lo, hi
        int side = 0;  // which end the last step moved: -1 lo, +1 hi
        for (int it = 0; it < 100 && std::abs(f) > tolerance; ++it) {
            t = hi - g_hi * (hi - lo) / (g_hi - g_lo);
            if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
            f = excess(t);
            if (f < 0) {
                lo = t, g_lo = f;
                if (side == -1) g_hi *= 0.5;
                side = -1;
            } else {
                hi = t, g_hi = f;
                if (side == 1) g_lo *= 0.5;
                side = 1;
            }
        }
        tau = t;
        x[k] = line.at(tau);
    }
    x[nk] = line.at(line.length);
}

// Surface numbers of the surface points next to surface point s: those of the 3x3x3 lattice
// block around it (edge and diagonal neighbours on its patch and across patch edges).
std::vector<Id> neighbours(const CubeSurfaceLattice& surface, Id s) {
    std::vector<Id> out;
    const LatticePoint p = surface.points[s];
    for (int dc = -1; dc <= 1; ++dc)
        for (int db = -1; db <= 1; ++db)
            for (int da = -1; da <= 1; ++da) {
                const LatticePoint q{p[0] + da, p[1] + db, p[2] + dc};
                const bool inside =
                    std::min({q[0], q[1], q[2]}) >= 0 && std::max({q[0], q[1], q[2]}) <= surface.n;
                if (!inside || (da == 0 && db == 0 && dc == 0)) continue;
                const Id t = surface.number_of(q);
                if (t >= 0) out.push_back(t);
            }
    return out;
}

// Distance from the wall over which each wall-normal line turns from the wall normal to its
// straight direction (before the cap of max_bend_per_diagonal): the whole line where the wall
// is convex; bend_per_focal_distance times the focal distance of the normals where they
// converge (concave wall, measured between neighbouring surface points: features finer than
// the lattice are not seen); in between, the smallest value of those plus bend_slope times
// the distance along the lattice.
std::vector<double> bend_lengths(const CubeSurfaceLattice& surface, const std::vector<Vec3>& wall,
                                 const std::vector<Vec3>& normal,
                                 const std::vector<double>& length) {
    const Id ns = surface.size();
    std::vector<double> bend(ns, std::numeric_limits<double>::infinity());
    std::vector<std::vector<Id>> adj(ns);
    for (Id s = 0; s < ns; ++s) {
        adj[s] = neighbours(surface, s);
        for (Id t : adj[s]) {
            const Vec3 dw = wall[t] - wall[s];
            const double converge = -dw.dot(normal[t] - normal[s]);
            if (converge > 0)  // focal distance dw^2 / converge
                bend[s] = std::min(bend[s], bend_per_focal_distance * dw.squaredNorm() / converge);
        }
    }
    // Lipschitz envelope by Dijkstra's algorithm over the lattice graph.
    using Item = std::pair<double, Id>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (Id s = 0; s < ns; ++s) queue.push({bend[s], s});
    while (!queue.empty()) {
        const auto [value, s] = queue.top();
        queue.pop();
        if (value > bend[s]) continue;
        for (Id t : adj[s]) {
            const double candidate = value + bend_slope * (wall[t] - wall[s]).norm();
            if (candidate < bend[t]) {
                bend[t] = candidate;
                queue.push({candidate, t});
            }
        }
    }
    for (Id s = 0; s < ns; ++s) bend[s] = std::min(bend[s], length[s]);
    return bend;
}

// A polyline with its arc length and a level rising along it.
struct LevelledLine {
    std::vector<Vec3> x;
    std::vector<double> arc, level;

    Vec3 at_arc(double a) const {
        const auto [k, w] = segment_at(a);
        return x[k - 1] + w * (x[k] - x[k - 1]);
    }
    double level_at_arc(double a) const {
        const auto [k, w] = segment_at(a);
        return level[k - 1] + w * (level[k] - level[k - 1]);
    }
    // The segment [k - 1, k] holding arc length a and the weight of x[k] there (a line has at
    // least two points: exterior_paths refuses shorter ones).
    std::pair<size_t, double> segment_at(double a) const {
        size_t k = std::upper_bound(arc.begin(), arc.end(), a) - arc.begin();
        k = std::clamp<size_t>(k, 1, x.size() - 1);
        return {k, std::clamp((a - arc[k - 1]) / std::max(arc[k] - arc[k - 1], 1e-300), 0.0, 1.0)};
    }
    // The first point at `c` (the level taken as non-decreasing: its running maximum).
    Vec3 at_level(double c) const {
        double running = level[0];
        for (size_t k = 1; k < x.size(); ++k) {
            const double next = std::max(running, level[k]);
            if (next >= c) {
                const double w = next > running ? (c - running) / (next - running) : 1.0;
                return x[k - 1] + std::clamp(w, 0.0, 1.0) * (x[k] - x[k - 1]);
            }
            running = next;
        }
        return x.back();
    }
};

// The nk - 1 inner nodes of every path's line (make_o_grid with paths), handed to set_line(s,
// x) with x[0] the wall node and x[nk] the far-field node.
template <class SetLine>
void place_nodes_on_paths(const WallPaths& paths, const std::vector<Vec3>& wall,
                          const std::vector<Vec3>& far, int nk, const WallLayers& law,
                          SetLine&& set_line) {
    const Id ns = Id(wall.size());
    const int m = std::min(law.layers, nk - 2);  // boundary-layer cells along the path
    const double growth = law.layers > 0 ? std::max(law.growth_ratio, 1.05) : 1.2;
    std::vector<LevelledLine> lines(ns);
    std::vector<double> top(ns);  // each line's level at the top of the boundary layer
    tbb::parallel_for(Id(0), ns, [&](Id s) {
        LevelledLine& l = lines[s];
        l.x = paths.lines[s];
        l.x.front() = wall[s];
        l.level = paths.levels[s];
        l.arc.assign(l.x.size(), 0);
        for (size_t k = 1; k < l.x.size(); ++k)
            l.arc[k] = l.arc[k - 1] + (l.x[k] - l.x[k - 1]).norm();
        top[s] = std::max(
            l.level_at_arc(m > 0 ? layers_thickness({law.first_height, law.growth_ratio, m}) : 0.0),
            1e-12 * paths.far_level);
    });
    // Cells between the boundary layer and the far surface, and from there to the far field:
    // as many growth-ratio steps as each part spans on a typical line.
    std::vector<double> sorted = top;
    std::nth_element(sorted.begin(), sorted.begin() + ns / 2, sorted.end());
    const double typical_top = sorted[ns / 2];
    double outer = 0, beyond = 0;
    for (Id s = 0; s < ns; ++s)
        outer += (lines[s].x.back() - paths.centre).norm() / double(ns),
            beyond += (far[s] - lines[s].x.back()).norm() / double(ns);
    const double level_steps = std::log(paths.far_level / typical_top) / std::log(growth);
    const double far_steps =
        std::log1p(beyond / std::max(outer, 1e-300) * (growth - 1)) / std::log(growth) + 1;
    const int free_cells = nk - m;
    const int level_cells = std::clamp(
        int(std::lround(free_cells * level_steps / (level_steps + far_steps))), 1, free_cells - 1);
    const int k_far = m + level_cells;  // the node on the far surface

    tbb::parallel_for(Id(0), ns, [&](Id s) {
        const LevelledLine& l = lines[s];
        std::vector<Vec3> x(nk + 1);
        x[0] = wall[s];
        double a = 0;
        for (int k = 1; k <= m; ++k) {
            a += law.first_height * std::pow(law.growth_ratio, k - 1);
            x[k] = l.at_arc(a);
        }
        const double lo = std::log(top[s]), hi = std::log(paths.far_level);
        for (int k = m + 1; k < k_far; ++k)
            x[k] = l.at_level(std::exp(lo + (hi - lo) * double(k - m) / double(k_far - m)));
        x[k_far] = l.x.back();
        // Beyond: geometric from the last cell's height to the far-field node.
        const double rest = (far[s] - x[k_far]).norm();
        const double first = std::max((x[k_far] - x[k_far - 1]).norm(), 1e-9 * rest);
        const int cells = nk - k_far;
        // Cells first q, first q^2, ... adding up to the rest (uniform if even `first` is too
        // long for them).
        const bool uniform = first * cells >= rest;
        const double q = uniform ? 1.0 : geometric_ratio(first, cells, rest);
        double d = 0, step = uniform ? rest / cells : first * q;
        for (int k = k_far + 1; k < nk; ++k) {
            d += step, step *= q;
            x[k] = x[k_far] + std::min(d / rest, 1.0) * (far[s] - x[k_far]);
        }
        x[nk] = far[s];
        set_line(s, x);
    });
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

}  // namespace

BlockGrid make_o_grid(const ImplicitFunction& body, const OGridOptions& options) {
    check_options(options);
    const int n = options.cells_per_edge, nk = options.layers;
    const Box3 box = body.bounds();
    const WallPaths* paths = options.paths;
    if (paths && (paths->cells_per_edge != n || paths->lines.empty()))
        throw std::invalid_argument("paths: a wall lattice made with other options");
    const Vec3 centre = paths ? paths->centre : options.centre.value_or(box.center());
    const Vec3 half = 0.5 * box.size();
    const double h = grid_length_scale(body, n);
    if (!paths)
        require_inside(body, centre);  // a continuation's centre needs only see its first level
    check_far_field(box, centre, options);

    const CubeSurfaceLattice surface = make_cube_surface_lattice(n);
    const Id ns = surface.size();
    if (options.wall_from && Id(options.wall_from->size()) != (nk + 1) * ns)
        throw std::invalid_argument("wall_from: the points of a grid made with other options");
    std::vector<Vec3> wall(ns), normal(ns), far(ns);
    std::vector<double> reach(ns);
    // The wall nodes: given, or the radial projections of the rays through the bounds' box,
    // then (box-like bodies: body_corners_by_octant) through the body's corners, so the patch
    // edges run along its edges.
    std::optional<CubeCorners> corners;
    const auto ray = [&](const LatticePoint& p) {
        return corners ? cube_sphere_ray(p, n, *corners) : cube_sphere_ray(p, n, half);
    };
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
        corners = corners_near_wall(body, centre, wall, h);
        if (corners) place_wall();
    } else if (options.patch_corners_on_body_corners) {
        // A given wall keeps the choice of the grid it came from: its 8 patch-corner nodes sit
        // on body corners exactly when that grid's rays spanned them, and they are those.
        std::array<Vec3, 8> at;
        for (int c = 0; c < 8; ++c)
            at[c] = wall[surface.number_of({c & 1 ? n : 0, c & 2 ? n : 0, c & 4 ? n : 0})];
        corners = corners_at_patch_corners(body, centre, at, h);
    }
    const Mat3 turn = corners ? corners_rotation(*corners) : Mat3::Identity();
    tbb::parallel_for(Id(0), ns, [&](Id s) {
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
    if (paths) {
        place_nodes_on_paths(*paths, wall, far, nk, options.wall_layers, set_line);
        return finish_o_grid(std::move(grid), surface, n, nk);
    }

    std::vector<double> length(ns);
    for (Id s = 0; s < ns; ++s) length[s] = (far[s] - wall[s]).norm();
    std::vector<double> bend = bend_lengths(surface, wall, normal, length);
    // Round a body with creases (a line leaving one along a bisector): on a smooth body the
    // cap only makes lines from a wall moved by the surface pass turn sooner (sphere at 1 M
    // cells: 4 Newton steps instead of 3, the same min scaled Jacobian).
    const bool creases =
        std::any_of(reach.begin(), reach.end(), [](double r) { return r > 1 + 1e-6; });
    if (creases)
        for (double& b : bend) b = std::min(b, max_bend_per_diagonal * box.diagonal());

    tbb::parallel_for(Id(0), ns, [&](Id s) {
        const WallNormalLine line{wall[s],   normal[s], (far[s] - wall[s]) / length[s],
                                  length[s], bend[s],   reach[s]};
        std::vector<Vec3> x;
        place_nodes(line, nk, options.wall_layers, x);
        set_line(s, x);
    });
    return finish_o_grid(std::move(grid), surface, n, nk);
}

}  // namespace hexmesh

#include "hexmesh/pipeline/exterior_paths.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "surface/level_sets.h"
#include "volume/cube_sphere.h"
#include "volume/o_h_grid.h"

namespace hexmesh {
namespace {

// The quads of the lattice on the unit sphere, slid there by the 2D functional with the target
// of each quad's own mean edge lengths: folds untangled, the rest barely moved.
void untangle_on_sphere(std::vector<Vec3>& directions, int n,
                        const untangle::UntangleOptions& solver) {
    untangle::Problem p;
    p.points = directions;
    p.kinds.assign(p.points.size(), VertexKind::slip);
    double total = 0;
    for (const std::array<Id, 4>& q : cube_surface_quads(make_cube_surface_lattice(n))) {
        const auto length = [&](int a, int b) { return (p.points[q[a]] - p.points[q[b]]).norm(); };
        // Mean lengths of the two pairs of opposite edges: (0-1, 3-2) and (0-3, 1-2).
        const double first = std::max(0.5 * (length(0, 1) + length(3, 2)), 1e-9);
        const double second = std::max(0.5 * (length(0, 3) + length(1, 2)), 1e-9);
        total += first + second;
        p.add_quad(q, first, second);
    }
    p.length_scale = total / (2.0 * 6 * n * n);
    p.surface_normal = [](Id, const Vec3& x) { return x; };
    p.project_to_surface = [](Id, const Vec3& x) { return Vec3(x.normalized()); };
    untangle::UntangleOptions o = solver;
    o.log = nullptr;
    o.max_optimize_iterations = std::min(o.max_optimize_iterations, 3);
    untangle::untangle_and_optimize(p, o);
    directions = std::move(p.points);
}

struct Climb {
    Vec3 point;
    double value;
};

// Where a line climbs out of a pocket of `potential` from x: on the nearest of the rings of 64
// directions at distances step, 2 step, 4 step and 8 step around x that has points higher than
// `above`, the highest of them. Not checked for passing through the body on the way: in a gap
// about as narrow as the lattice the interpolant is <= 0 next to the line (it is 0 on the body
// only to second order), and a check there stops the lines it is for (homer's chin). A climb
// can therefore jump across a part thinner than 2 steps.
std::optional<Climb> climb_out(const ImplicitFunction& potential, const Vec3& x, double above,
                               double step) {
    static const std::vector<Vec3> around = sphere_directions(64);
    for (double r = step; r <= 8 * step; r *= 2) {
        std::optional<Climb> best;
        for (const Vec3& d : around) {
            const Vec3 y = x + r * d;
            const double fy = potential.value(y);
            if (fy > (best ? best->value : above)) best = Climb{y, fy};
        }
        if (best) return best;
    }
    return std::nullopt;
}

// A point of the segment from p (F < c0) to q (F >= c0) where F = c0, by bisection.
Vec3 on_level(const ImplicitFunction& potential, Vec3 p, Vec3 q, double c0) {
    for (int i = 0; i < 40; ++i) {
        const Vec3 m = 0.5 * (p + q);
        (potential.value(m) >= c0 ? q : p) = m;
    }
    return 0.5 * (p + q);
}

// The unit gradient of `potential` at x (zero where it vanishes or is not finite).
Vec3 uphill(const ImplicitFunction& potential, const Vec3& x) {
    const Vec3 g = potential.gradient(x);
    const double norm = g.norm();
    return norm > 0 && std::isfinite(norm) ? Vec3(g / norm) : Vec3(Vec3::Zero());
}

}  // namespace

std::vector<Vec3> gradient_line_up(const ImplicitFunction& potential, Vec3 p, double c0,
                                   double step, std::vector<double>& levels, bool climb_pockets) {
    const double longest = 4 * potential.bounds().diagonal();
    const auto up = [&](const Vec3& x) { return uphill(potential, x); };
    std::vector<Vec3> line = {p};
    double f = potential.value(p);
    levels = {std::max(f, 0.0)};
    double highest = f;  // F at the line's highest point so far (levels clamp it at 0)
    int flat = 0;        // steps in a row that did not rise above it
    for (double travelled = 0; travelled < longest && f < c0; travelled += step) {
        const Vec3 v = up(p);
        Vec3 q = p;
        double fq = f;
        if (v.squaredNorm() > 0) {
            const Vec3 w = up(p + 0.5 * step * v);
            q = p + step * (w.squaredNorm() > 0 ? w : v);
            fq = potential.value(q);
        }
        if (v.squaredNorm() == 0 && !climb_pockets) break;
        flat = fq > highest ? 0 : flat + 1;
        if (climb_pockets && (v.squaredNorm() == 0 || flat >= 4)) {
            // The gradient vanishes, or the line has not risen for 4 steps: a gap about as
            // narrow as the potential's lattice, where F is near its solve's noise and the
            // interpolant has pockets.
            const std::optional<Climb> out = climb_out(potential, p, highest, step);
            if (!out) break;
            q = out->point;
            fq = out->value;
            flat = 0;
            if (fq >= c0)
                q = on_level(potential, p, q, c0);  // a climb does not follow the gradient
        } else if (fq >= c0 && fq > f) {
            q = p + (q - p) * ((c0 - f) / (fq - f));  // land on the level
        }
        highest = std::max(highest, fq);
        p = q;
        f = std::min(fq, c0);
        line.push_back(p);
        levels.push_back(std::max(f, levels.back()));
    }
    return line;
}

std::vector<Vec3> direction_line_up(const ImplicitFunction& potential,
                                    const HarmonicDirections& theta, Vec3 p, double c0, double step,
                                    double along_gradient, std::vector<double>& levels) {
    const double longest = 4 * potential.bounds().diagonal();
    const auto up = [&](const Vec3& x) { return uphill(potential, x); };
    std::vector<Vec3> line = {p};
    double f = potential.value(p);
    levels = {std::max(f, 0.0)};
    const auto add = [&](Vec3 q) {
        double fq = potential.value(q);
        if (fq >= c0 && fq > f) {
            q = line.back() + (q - line.back()) * ((c0 - f) / (fq - f));
            fq = c0;
        }
        line.push_back(q);
        f = std::min(fq, c0);
        levels.push_back(std::max(f, levels.back()));
    };
    double travelled = 0;
    // First along the gradient: the boundary layer's lines leave the wall at right angles.
    for (; travelled < along_gradient && f < c0; travelled += step) {
        const Vec3 v = up(line.back());
        if (v.squaredNorm() == 0) break;
        const Vec3 w = up(line.back() + 0.5 * step * v);
        add(line.back() + step * (w.squaredNorm() > 0 ? w : v));
    }
    const Vec3 start = theta.value(line.back());
    if (!(start.norm() > 1e-9)) return line;
    const Vec3 d = start.normalized();
    const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);
    // The fibre's constraints a = theta . e1 = 0, b = theta . e2 = 0: their gradients.
    const auto constraints = [&](const Vec3& x) {
        const Mat3 J = theta.jacobian(x);
        Eigen::Matrix<double, 2, 3> A;
        A.row(0) = (J.transpose() * e1).transpose();
        A.row(1) = (J.transpose() * e2).transpose();
        return A;
    };
    const auto tangent = [&](const Vec3& x, const Vec3& previous) -> Vec3 {
        const Eigen::Matrix<double, 2, 3> A = constraints(x);
        Vec3 t = Vec3(A.row(0).transpose()).cross(Vec3(A.row(1).transpose()));
        if (!(t.norm() > 0) || !t.allFinite()) return Vec3::Zero();
        t.normalize();
        return t.dot(previous) < 0 ? Vec3(-t) : t;
    };
    // Back onto the fibre (Gauss-Newton, the least-norm correction, at most a step long).
    const auto onto_fibre = [&](Vec3 x) {
        for (int it = 0; it < 3; ++it) {
            const Vec3 th = theta.value(x);
            const Eigen::Vector2d r(th.dot(e1), th.dot(e2));
            const Eigen::Matrix<double, 2, 3> A = constraints(x);
            const Eigen::Matrix2d AAt = A * A.transpose();
            if (!(std::abs(AAt.determinant()) > 1e-300)) break;
            Vec3 dx = -A.transpose() * AAt.inverse() * r;
            if (dx.norm() > step) dx *= step / dx.norm();
            x += dx;
        }
        return x;
    };
    Vec3 previous = up(line.back());
    if (previous.squaredNorm() == 0) previous = d;
    for (; travelled < longest && f < c0; travelled += step) {
        const Vec3 t = tangent(line.back(), previous);
        if (t.squaredNorm() == 0) break;
        const Vec3 m = tangent(line.back() + 0.5 * step * t, t);
        const Vec3 q = onto_fibre(line.back() + step * (m.squaredNorm() > 0 ? m : t));
        if (!(theta.value(q).dot(d) > 0)) break;  // the fibre of -d
        previous = (q - line.back()).normalized();
        add(q);
    }
    return line;
}

namespace {

// Whether path s ends below the level c0.
bool short_of_level(const WallPaths& paths, size_t s) {
    return paths.levels[s].back() < (1 - 1e-9) * paths.far_level;
}

// The gradient lines of the wall nodes up to c0, each traced again climbing out of pockets
// when it stops short (see exterior_paths); far_directions left empty.
WallPaths trace_paths(const ImplicitFunction& potential, const std::vector<Vec3>& wall, double c0,
                      int n, const Vec3& centre, const HarmonicDirections* directions = nullptr) {
    WallPaths paths;
    paths.cells_per_edge = n;
    paths.centre = centre;
    paths.far_level = c0;
    paths.lines.resize(wall.size());
    paths.levels.resize(wall.size());
    const double step = 0.25 * grid_length_scale(potential, n);
    std::atomic<Id> fibres{0};
    tbb::parallel_for(size_t(0), wall.size(), [&](size_t s) {
        if (directions) {
            // A wall edge up the gradient first, for the boundary layer.
            paths.lines[s] = direction_line_up(potential, *directions, wall[s], c0, step, 4 * step,
                                               paths.levels[s]);
            if (!short_of_level(paths, s)) {
                ++fibres;
                return;
            }
        }
        paths.lines[s] = gradient_line_up(potential, wall[s], c0, step, paths.levels[s]);
        if (short_of_level(paths, s))
            paths.lines[s] = gradient_line_up(potential, wall[s], c0, step, paths.levels[s], true);
    });
    paths.fibres = fibres;
    return paths;
}

}  // namespace

WallPaths interior_paths(const ImplicitFunction& potential, const std::vector<Vec3>& wall,
                         double c0, int n, const Vec3& centre) {
    WallPaths paths = trace_paths(potential, wall, c0, n, centre);
    for (size_t s = 0; s < wall.size(); ++s)
        if (short_of_level(paths, s)) {
            paths.lines[s] = {wall[s]};
            paths.levels[s] = {0.0};
        }
    return paths;
}

WallPaths exterior_paths(const ImplicitFunction& potential, const std::vector<Vec3>& wall,
                         double c0, int n, const Vec3& centre,
                         const untangle::UntangleOptions& solver, LevelSpreading* spread,
                         const HarmonicDirections* theta) {
    WallPaths paths = trace_paths(potential, wall, c0, n, centre, theta);
    std::vector<Vec3> directions(wall.size());
    for (size_t s = 0; s < wall.size(); ++s) {
        // A line that stopped short of the far level (no higher point near its end, or it
        // wandered four diagonals) would pile its nodes on its last point.
        if (paths.lines[s].size() < 2 || short_of_level(paths, s))
            throw std::invalid_argument(fmt::format(
                "the exterior potential's gradient line from the wall point ({:.4g}, {:.4g}, "
                "{:.4g}) stops at level {:.3g} short of the far level {:.3g} (no higher point "
                "near its end)",
                wall[s].x(), wall[s].y(), wall[s].z(), paths.levels[s].back(), c0));
    }
    if (spread) *spread = spread_on_levels(potential, paths, solver);
    for (size_t s = 0; s < wall.size(); ++s) {
        const Vec3 d = paths.outer(s) - centre;
        if (!d.allFinite() || !(d.norm() > 0))
            throw std::runtime_error("the gradient line of a wall node left no finite point");
        directions[s] = d.normalized();
    }
    untangle_on_sphere(directions, n, solver);
    paths.far_directions = std::move(directions);
    return paths;
}

}  // namespace hexmesh

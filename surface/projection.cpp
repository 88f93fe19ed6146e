// project_to_surface (steps of V, watchdog, bracketing and backtracking) and tangent frames.
#include "surface/projection.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hexmesh {

namespace {

constexpr double tiny_gradient = 1e-12;
constexpr double max_step_factor = 4.0;  // a projection step is at most this times |u|
constexpr int max_halvings = 40;
constexpr int max_bisections = 200;
constexpr double march_safety = 0.9;     // sphere-tracing step as a fraction of |u|
constexpr double march_min_step = 1e-3;  // relative to length_scale
constexpr int max_march_steps = 1000000;

// True when going from a value a to b crosses (or touches) u = 0; a is never 0 here.
bool crosses(double a, double b) {
    return a < 0 ? b >= 0 : b <= 0;
}

struct Sample {
    Vec3 x;
    double f;
};

// Root of u on the segment [a, b] where u changes sign, by the Illinois variant of regula
// falsi (a secant that cannot stall), to |u| < tol or until the segment stops shrinking.
// Returns the best sample seen; adds the evaluations to *steps.
Sample refine_bracket(const ImplicitFunction& u, Sample a, Sample b, double tol, int* steps) {
    Sample best = std::abs(a.f) < std::abs(b.f) ? a : b;
    const Vec3 origin = a.x;
    const Vec3 span = b.x - a.x;
    double s0 = 0, f0 = a.f, s1 = 1, f1 = b.f;
    int last_side = 0;
    for (int i = 0; i < max_bisections && std::abs(best.f) >= tol; ++i) {
        double s = (s0 * f1 - s1 * f0) / (f1 - f0);
        if (!(s > s0 && s < s1)) s = 0.5 * (s0 + s1);
        const Vec3 x = origin + s * span;
        const double f = u.value(x);
        ++*steps;
        if (!std::isfinite(f)) break;
        if (std::abs(f) < std::abs(best.f)) best = {x, f};
        if (crosses(f0, f)) {
            s1 = s;
            f1 = f;
            if (last_side == 1) f0 *= 0.5;
            last_side = 1;
        } else {
            s0 = s;
            f0 = f;
            if (last_side == -1) f1 *= 0.5;
            last_side = -1;
        }
        const Vec3 lo = origin + s0 * span, hi = origin + s1 * span;
        if (lo == hi || (hi - lo).norm() <= 4 * std::numeric_limits<double>::epsilon() *
                                                std::max(1.0, lo.cwiseAbs().maxCoeff()))
            break;
    }
    return best;
}

// Sphere tracing from `start` along the unit vector d for a length up to t_max: the first
// pair of samples with a sign change, or nullopt.
std::optional<std::pair<Sample, Sample>> march_to_crossing(const ImplicitFunction& u,
                                                           const Sample& start, const Vec3& d,
                                                           double t_max, double min_step) {
    double t = 0;
    Sample prev = start;
    for (int i = 0; i < max_march_steps && t < t_max; ++i) {
        t = std::min(t + std::max(march_safety * std::abs(prev.f), min_step), t_max);
        const Vec3 x = start.x + t * d;
        const Sample next{x, u.value(x)};
        if (!std::isfinite(next.f)) return std::nullopt;
        if (crosses(start.f, next.f)) return std::make_pair(prev, next);
        prev = next;
    }
    return std::nullopt;
}

// A direction that should reach the surface when the gradient gives none: away from the
// body's box centre from inside, towards it from outside.
Vec3 fallback_direction(const ImplicitFunction& u, const Vec3& x, double f) {
    Vec3 v = x - u.bounds().center();
    if (!(v.norm() > 0)) v = Vec3::UnitZ();
    return (f < 0 ? 1.0 : -1.0) * v.normalized();
}

// One step of V from s: the unit direction d along which |u| should decrease and the step
// length tau |u| / |grad u|, at most max_step_factor |u|. Where the gradient vanishes, d is
// `fallback` (or a direction from the bounds if that is zero), the length |u| and g = 0.
struct Step {
    Vec3 d;
    double alpha;
    Vec3 g;  // grad u at s
};
Step v_step(const ImplicitFunction& u, const Sample& s, double tau, const Vec3& fallback) {
    const Vec3 g = u.gradient(s.x);
    const double gn = g.norm();
    const double f = std::abs(s.f);
    if (std::isfinite(gn) && gn >= tiny_gradient)
        return {(s.f > 0 ? -1.0 : 1.0) * g / gn, std::min(tau * f / gn, max_step_factor * f), g};
    const Vec3 d = fallback.norm() > 0 ? fallback : fallback_direction(u, s.x, s.f);
    return {d, f, Vec3::Zero()};
}

// The nearest point to a where the linear models of u at a (gradient ga) and at b (gb) both
// vanish: the step onto a crease when a and b see different pieces of a CSG body, where
// plain steps would zigzag between the two surfaces. nullopt if the gradients are parallel.
std::optional<Vec3> crease_point(const Sample& a, const Vec3& ga, const Sample& b, const Vec3& gb) {
    if (ga.cross(gb).norm() < 1e-3 * ga.norm() * gb.norm()) return std::nullopt;
    Eigen::Matrix<double, 2, 3> jacobian;
    jacobian << ga.transpose(), gb.transpose();
    const Eigen::Vector2d rhs(-a.f, -b.f - gb.dot(a.x - b.x));
    const Eigen::Vector2d y = (jacobian * jacobian.transpose()).inverse() * rhs;
    return Vec3(a.x + jacobian.transpose() * y);
}

Sample sample(const ImplicitFunction& u, const Vec3& x) {
    return {x, u.value(x)};
}

// The watchdog after a step v from cur to `next` (finite) that removed too little of |u|:
// the step may have entered another piece of a CSG body (inside a union u only bounds the
// distance). Aims at the crease of the two pieces, or takes one more plain step from next;
// the sample reached if its |u| is at most `wanted`, else nullopt.
std::optional<Sample> watchdog_step(const ImplicitFunction& u, const Sample& cur, const Step& v,
                                    const Sample& next, double tau, double wanted) {
    const Step w = v_step(u, next, tau, v.d);
    std::optional<Sample> after;
    if (v.g.norm() > 0 && w.g.norm() > 0) {
        if (auto x = crease_point(cur, v.g, next, w.g);
            x && (*x - cur.x).norm() <= max_step_factor * (std::abs(cur.f) + v.alpha))
            after = sample(u, *x);
    }
    if (!after || !(std::abs(after->f) <= wanted)) after = sample(u, next.x + w.alpha * w.d);
    if (std::abs(after->f) <= wanted) return after;
    return std::nullopt;
}

// Backtracking: the first of the steps v halved (up to max_halvings times) that reduces |u|
// replaces cur; false when none does.
bool backtrack(const ImplicitFunction& u, const Step& v, Sample& cur) {
    double alpha = 0.5 * v.alpha;
    for (int h = 0; h < max_halvings; ++h, alpha *= 0.5) {
        const Sample shorter = sample(u, cur.x + alpha * v.d);
        if (std::abs(shorter.f) < std::abs(cur.f)) {
            cur = shorter;
            return true;
        }
    }
    return false;
}

}  // namespace

Projection project_to_surface(const ImplicitFunction& u, const Vec3& p, double length_scale,
                              const ProjectionOptions& options) {
    if (!(length_scale > 0) || !std::isfinite(length_scale))
        throw std::invalid_argument("project_to_surface: length_scale must be positive, got " +
                                    std::to_string(length_scale));
    const double tol = options.tolerance * length_scale;
    const double tau = options.relaxation;
    // A step is good when it removes at least half of what an exact distance would lose.
    const double good = std::min(0.5 * (1 + std::abs(1 - tau)), 0.99);
    const Box3 box = u.bounds();
    const double min_step = march_min_step * length_scale;

    Sample cur = sample(u, p);
    Projection result{p, std::abs(cur.f), 0, false};
    if (!std::isfinite(cur.f)) {
        result.residual = std::numeric_limits<double>::infinity();
        return result;
    }
    Vec3 last_direction = Vec3::Zero();
    int stalled = 0;  // consecutive steps that only backtracking could make

    for (int step = 0; step < options.max_iterations && std::abs(cur.f) >= tol; ++step) {
        ++result.iterations;
        const Step v = v_step(u, cur, tau, last_direction);
        last_direction = v.d;
        const double wanted = good * std::abs(cur.f);
        const Sample next = sample(u, cur.x + v.alpha * v.d);
        if (std::abs(next.f) <= wanted) {
            cur = next;
            stalled = 0;
            continue;
        }
        if (crosses(cur.f, next.f)) {  // jumped over the surface: it lies in between
            cur = refine_bracket(u, cur, next, tol, &result.iterations);
            continue;
        }
        // Watchdog: the step may have entered another piece of a CSG body.
        if (std::isfinite(next.f))
            if (const auto after = watchdog_step(u, cur, v, next, tau, wanted)) {
                ++result.iterations;
                cur = *after;
                stalled = 0;
                continue;
            }
        // Look for the surface along the line of the step, forwards; after repeated
        // stalls (a spurious critical point of u) along the line to the bounds' centre.
        const double reach = box.diagonal() + (cur.x - box.center()).norm() + std::abs(cur.f);
        const Vec3 line = stalled >= 3 ? fallback_direction(u, cur.x, cur.f) : v.d;
        auto bracket = march_to_crossing(u, cur, line, reach, min_step);
        if (bracket) {
            cur = refine_bracket(u, bracket->first, bracket->second, tol, &result.iterations);
            stalled = 0;
            continue;
        }
        // Backtracking: any shorter step that reduces |u|.
        ++stalled;
        if (backtrack(u, v, cur)) continue;
        bracket = march_to_crossing(u, cur, -v.d, reach, min_step);
        if (!bracket) break;
        cur = refine_bracket(u, bracket->first, bracket->second, tol, &result.iterations);
    }

    result.point = cur.x;
    result.residual = std::abs(cur.f);
    result.converged = result.residual < tol;
    return result;
}

TangentFrame tangent_frame(const ImplicitFunction& u, const Vec3& p) {
    const Vec3 g = u.gradient(p);
    const double gn = g.norm();
    TangentFrame frame;
    frame.normal = (std::isfinite(gn) && gn >= tiny_gradient) ? Vec3(g / gn) : Vec3::UnitZ();
    // Start t1 from the coordinate axis least aligned with the normal: well conditioned.
    int axis = 0;
    frame.normal.cwiseAbs().minCoeff(&axis);
    const Vec3 e = Vec3::Unit(axis);
    frame.t1 = (e - frame.normal.dot(e) * frame.normal).normalized();
    frame.t2 = frame.normal.cross(frame.t1);
    return frame;
}

std::optional<Vec3> intersect_ray(const ImplicitFunction& u, const Vec3& origin,
                                  const Vec3& direction, double length_scale) {
    const double dn = direction.norm();
    if (!(dn > 0) || !std::isfinite(dn))
        throw std::invalid_argument("intersect_ray: the direction must be a non-zero vector");
    if (!(length_scale > 0) || !std::isfinite(length_scale))
        throw std::invalid_argument("intersect_ray: length_scale must be positive, got " +
                                    std::to_string(length_scale));
    const Vec3 d = direction / dn;
    const double tol = 1e-12 * length_scale;
    const Sample start{origin, u.value(origin)};
    if (!std::isfinite(start.f)) return std::nullopt;
    if (std::abs(start.f) < tol) return origin;

    // Parameter range of the ray inside the (slightly padded) bounds: surface points on the
    // box faces must not be lost to rounding.
    Box3 box = u.bounds();
    const Vec3 pad = Vec3::Constant(1e-6 * length_scale + 1e-9 * box.diagonal());
    box.lo -= pad;
    box.hi += pad;
    double t_enter = 0, t_exit = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) {
            if (origin[a] < box.lo[a] || origin[a] > box.hi[a]) return std::nullopt;
            continue;
        }
        const double t0 = (box.lo[a] - origin[a]) / d[a];
        const double t1 = (box.hi[a] - origin[a]) / d[a];
        t_enter = std::max(t_enter, std::min(t0, t1));
        t_exit = std::min(t_exit, std::max(t0, t1));
    }
    if (t_exit <= t_enter) return std::nullopt;

    // Outside the box u keeps the origin's sign, so the march may start at the entry.
    Sample entry = start;
    if (t_enter > 0) {
        entry.x = origin + t_enter * d;
        entry.f = u.value(entry.x);
        if (crosses(start.f, entry.f)) {
            int steps = 0;
            return refine_bracket(u, start, entry, tol, &steps).x;
        }
    }
    const auto bracket =
        march_to_crossing(u, entry, d, t_exit - t_enter, march_min_step * length_scale);
    if (!bracket) return std::nullopt;
    int steps = 0;
    return refine_bracket(u, bracket->first, bracket->second, tol, &steps).x;
}

}  // namespace hexmesh

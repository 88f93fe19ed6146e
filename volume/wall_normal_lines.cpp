// The O-grid's lines from the wall to the far field: each leaves along its wall normal (at a
// crease or corner, the bisector), turns towards its far-field node over a bend length that
// keeps lines from a concave wall apart, and carries nodes graded by the wall-layer law.
#include "volume/wall_normal_lines.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "hexmesh/core/deterministic_for.h"

namespace hexmesh {
namespace {

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
    const std::vector<double> d = wall_distances(line.length, nk, law, &line.wall);
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
    const std::vector<double> a = wall_distances(arc, nk, law, &line.wall);

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

}  // namespace

void place_nodes_on_lines(const CubeSurfaceLattice& surface, const std::vector<Vec3>& wall,
                          const std::vector<Vec3>& normal, const std::vector<double>& reach,
                          const std::vector<Vec3>& far, double diagonal, int nk,
                          const WallLayers& law,
                          const std::function<void(Id, const std::vector<Vec3>&)>& set_line) {
    const Id ns = surface.size();
    std::vector<double> length(ns);
    for (Id s = 0; s < ns; ++s) length[s] = (far[s] - wall[s]).norm();
    std::vector<double> bend = bend_lengths(surface, wall, normal, length);
    // Round a body with creases (a line leaving one along a bisector): on a smooth body the
    // cap only makes lines from a wall moved by the surface pass turn sooner (sphere at 1 M
    // cells: 4 Newton steps instead of 3, the same min scaled Jacobian).
    const bool creases =
        std::any_of(reach.begin(), reach.end(), [](double r) { return r > 1 + 1e-6; });
    if (creases)
        for (double& b : bend) b = std::min(b, max_bend_per_diagonal * diagonal);

    deterministic_for(ns, [&](Id s) {
        const WallNormalLine line{wall[s],   normal[s], (far[s] - wall[s]) / length[s],
                                  length[s], bend[s],   reach[s]};
        std::vector<Vec3> x;
        place_nodes(line, nk, law, x);
        set_line(s, x);
    });
}

}  // namespace hexmesh

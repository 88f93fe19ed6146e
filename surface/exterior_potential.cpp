// ExteriorPotential: the lattice, the finite-difference solve and the trilinear interpolation.
#include "surface/exterior_potential.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hexmesh/core/parallel_sum.h"

namespace hexmesh {
namespace {

enum class NodeKind : unsigned char { free, body, box };

// The 6 face neighbours' offsets in the flat node numbering.
std::array<long long, 6> neighbour_offsets(const std::array<int, 3>& n) {
    const long long sx = 1, sy = n[0], sz = (long long)n[0] * n[1];
    return {-sx, sx, -sy, sy, -sz, sz};
}

constexpr size_t sum_grain = 1 << 14;  // the conjugate gradients' dot products (deterministic_sum)

template <class F>
void parallel_each(size_t count, F&& f) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1 << 14),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i) f(i);
                      });
}

// The boundary rule of Gibou et al.: the wall lies at theta h from the free node, towards a
// neighbour inside the body (u changes sign linearly); the coupling becomes 1 / theta.
constexpr double min_theta = 0.05;

// The body's value u at each node of the lattice (n[a] nodes along axis a from lo, spacing
// h, node id i + n[0] (j + n[1] k)) and the node's kind: box on the lattice's faces, else
// body where u <= 0, else free. For the interior potential (o.source_radius > 0), -u, and the
// nodes in the source ball are "box" (F = 1) instead of the lattice's faces.
void sample_nodes(const ImplicitFunction& body, const Vec3& lo, double h,
                  const std::array<int, 3>& n, const ExteriorPotentialOptions& o,
                  std::vector<double>& u, std::vector<double>& source,
                  std::vector<NodeKind>& kind) {
    const bool interior = o.source_radius > 0;
    const size_t count = size_t(n[0]) * n[1] * n[2];
    source.assign(interior ? count : 0, 0.0);
    u.resize(count);
    kind.resize(count);
    parallel_each(count, [&](size_t id) {
        const int i = int(id % n[0]), j = int((id / n[0]) % n[1]),
                  k = int(id / (size_t(n[0]) * n[1]));
        const Vec3 x = lo + h * Vec3(i, j, k);
        u[id] = interior ? -body.value(x) : body.value(x);
        const bool face =
            i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        if (interior) source[id] = (x - o.source_centre).norm() - o.source_radius;
        const bool one = interior ? source[id] <= 0 && u[id] > 0 : face;
        kind[id] = one ? NodeKind::box : u[id] <= 0 || face ? NodeKind::body : NodeKind::free;
    });
}

// The operator (A x)_i = diag_i x_i - sum of x over free neighbours, on the free nodes, and
// its right side: diag and rhs (zero on the other nodes). With `source` (the interior
// potential's |x - centre| - radius at each node), its ball's sphere is placed between nodes
// as the body's is, at value 1.
void assemble_operator(const std::vector<NodeKind>& kind, const std::vector<double>& u,
                       const std::vector<double>& source, const std::array<long long, 6>& step,
                       std::vector<double>& diag, std::vector<double>& rhs) {
    const size_t count = kind.size();
    diag.assign(count, 0);
    rhs.assign(count, 0);
    parallel_each(count, [&](size_t id) {
        if (kind[id] != NodeKind::free) return;
        for (long long s : step) {
            const size_t m = size_t((long long)id + s);
            if (kind[m] == NodeKind::body) {
                diag[id] += 1 / std::max(min_theta, u[id] / (u[id] - u[m]));
            } else if (kind[m] == NodeKind::box && !source.empty()) {
                const double coupling =
                    1 / std::max(min_theta, source[id] / (source[id] - source[m]));
                diag[id] += coupling;
                rhs[id] += coupling;
            } else {
                diag[id] += 1;
                if (kind[m] == NodeKind::box) rhs[id] += 1;
            }
        }
    });
}

// A x = rhs on the free nodes by preconditioned conjugate gradients (Jacobi), from x (0 on the
// other nodes), to the relative residual o.tolerance.
// Throws std::runtime_error when o.max_iterations do not reach it.
std::vector<double> solve_potential(const std::vector<NodeKind>& kind, std::vector<double> x,
                                    const std::vector<double>& diag, const std::vector<double>& rhs,
                                    const std::array<long long, 6>& step,
                                    const ExteriorPotentialOptions& o, int& iterations) {
    const size_t count = kind.size();
    const auto apply = [&](const std::vector<double>& x, std::vector<double>& y) {
        parallel_each(count, [&](size_t id) {
            if (kind[id] != NodeKind::free) return void(y[id] = 0);
            double sum = diag[id] * x[id];
            for (long long s : step) sum -= x[size_t((long long)id + s)];  // 0 unless free
            y[id] = sum;
        });
    };
    std::vector<double> r(count), z(count), p(count), q(count);
    apply(x, q);
    parallel_each(count,
                  [&](size_t id) { r[id] = kind[id] == NodeKind::free ? rhs[id] - q[id] : 0; });
    const double norm_b = std::sqrt(
        deterministic_sum(count, sum_grain, [&](size_t id) { return rhs[id] * rhs[id]; }));
    parallel_each(count,
                  [&](size_t id) { z[id] = kind[id] == NodeKind::free ? r[id] / diag[id] : 0; });
    p = z;
    double rz = deterministic_sum(count, sum_grain, [&](size_t id) { return r[id] * z[id]; });
    double residual =
        std::sqrt(deterministic_sum(count, sum_grain, [&](size_t id) { return r[id] * r[id]; }));
    int it = 0;
    for (; it < o.max_iterations && residual > o.tolerance * norm_b; ++it) {
        apply(p, q);
        const double alpha =
            rz / deterministic_sum(count, sum_grain, [&](size_t id) { return p[id] * q[id]; });
        parallel_each(count, [&](size_t id) {
            x[id] += alpha * p[id];
            r[id] -= alpha * q[id];
            z[id] = kind[id] == NodeKind::free ? r[id] / diag[id] : 0;
        });
        const double rz_next =
            deterministic_sum(count, sum_grain, [&](size_t id) { return r[id] * z[id]; });
        const double beta = rz_next / rz;
        rz = rz_next;
        parallel_each(count, [&](size_t id) { p[id] = z[id] + beta * p[id]; });
        residual = std::sqrt(
            deterministic_sum(count, sum_grain, [&](size_t id) { return r[id] * r[id]; }));
    }
    iterations = it;
    if (residual > o.tolerance * norm_b)
        throw std::runtime_error(fmt::format(
            "the {} potential did not converge in {} iterations (relative residual {:.3g})",
            o.source_radius > 0 ? "interior" : "exterior", it, residual / norm_b));
    return x;
}

// The node values: x on the free nodes, 1 on the box, and inside the body u times the slope
// F / u of the free neighbours (their mean), or of all nodes next to the body where a node
// has no free neighbour.
std::vector<double> extend_into_body(const std::vector<NodeKind>& kind,
                                     const std::vector<double>& u, const std::vector<double>& x,
                                     const std::array<long long, 6>& step, double margin) {
    const size_t count = kind.size();
    std::vector<double> values(count, 1.0);
    std::vector<double> slope(count, 0);
    parallel_each(count, [&](size_t id) {
        if (kind[id] == NodeKind::free) values[id] = x[id];
        if (kind[id] != NodeKind::body) return;
        double sum = 0;
        int found = 0;
        for (long long s : step) {
            const long long m = (long long)id + s;
            if (m < 0 || m >= (long long)count || kind[m] != NodeKind::free) continue;
            sum += x[m] / u[m];
            ++found;
        }
        if (found) slope[id] = sum / found;
    });
    double total = 0;
    long long counted = 0;
    for (size_t id = 0; id < count; ++id)
        if (slope[id] > 0) total += slope[id], ++counted;
    const double mean_slope = counted ? total / double(counted) : 1 / margin;
    parallel_each(count, [&](size_t id) {
        if (kind[id] == NodeKind::body)
            values[id] = u[id] * (slope[id] > 0 ? slope[id] : mean_slope);
    });
    return values;
}

// The potential's lattice round the body: its box, spacing and node counts. Throws
// std::invalid_argument for bad options or bounds.
struct Lattice {
    Box3 box;
    double h = 0;
    std::array<int, 3> n{};

    Vec3 node(size_t id) const {
        return box.lo + h * Vec3(double(id % n[0]), double((id / n[0]) % n[1]),
                                 double(id / (size_t(n[0]) * n[1])));
    }
};

Lattice make_lattice(const ImplicitFunction& body, const ExteriorPotentialOptions& o) {
    if (!(o.margin > 0) || o.resolution < 8 || !(o.tolerance > 0) || o.max_iterations < 1)
        throw std::invalid_argument(
            "ExteriorPotential: margin, resolution (>= 8), tolerance and "
            "iterations must be positive");
    const Box3 b = body.bounds();
    const double longest = b.size().maxCoeff();
    if (!(longest > 0 && std::isfinite(longest) && b.lo.allFinite()))
        throw std::invalid_argument("ExteriorPotential: the body's bounds are empty or not finite");
    Lattice l;
    l.h = longest / o.resolution;
    const Vec3 lo = b.lo - Vec3::Constant(o.margin * longest);
    for (int a = 0; a < 3; ++a)
        l.n[a] = int(std::ceil((b.size()[a] + 2 * o.margin * longest) / l.h)) + 1;
    l.box = {lo, lo + l.h * Vec3(l.n[0] - 1, l.n[1] - 1, l.n[2] - 1)};
    return l;
}

// The cell of the lattice holding p (inside the box): its lowest node and p's place in it,
// [0, 1]^3.
std::pair<std::array<int, 3>, Vec3> lattice_cell(const Box3& box, double h,
                                                 const std::array<int, 3>& n, const Vec3& p) {
    const Vec3 q = (p - box.lo) / h;
    const std::array<int, 3> c = {std::clamp(int(q.x()), 0, n[0] - 2),
                                  std::clamp(int(q.y()), 0, n[1] - 2),
                                  std::clamp(int(q.z()), 0, n[2] - 2)};
    return {c, q - Vec3(c[0], c[1], c[2])};
}

// Calls f(id, weight, gradient) for each of the 8 nodes of the lattice cell whose lowest node
// is c (n nodes along each axis), at the place t in it: the node's trilinear weight and that
// weight's gradient in cell units (exact for the interpolant).
template <class F>
void for_cell_nodes(const std::array<int, 3>& n, const std::array<int, 3>& c, const Vec3& t,
                    F&& f) {
    for (int corner = 0; corner < 8; ++corner) {
        const int a = corner & 1, b = (corner >> 1) & 1, d = corner >> 2;
        const Vec3 w(a ? t.x() : 1 - t.x(), b ? t.y() : 1 - t.y(), d ? t.z() : 1 - t.z());
        const Vec3 dw(a ? 1 : -1, b ? 1 : -1, d ? 1 : -1);
        f(size_t(c[0] + a) + size_t(n[0]) * (size_t(c[1] + b) + size_t(n[1]) * size_t(c[2] + d)),
          w.x() * w.y() * w.z(),
          Vec3(dw.x() * w.y() * w.z(), w.x() * dw.y() * w.z(), w.x() * w.y() * dw.z()));
    }
}

}  // namespace

ExteriorPotential::ExteriorPotential(const ImplicitFunction& body,
                                     const ExteriorPotentialOptions& o) {
    const Lattice lattice = make_lattice(body, o);
    h_ = lattice.h;
    n_ = lattice.n;
    box_ = lattice.box;
    const Vec3 lo = box_.lo;
    const double longest = body.bounds().size().maxCoeff();

    std::vector<double> u, source, diag, rhs;
    std::vector<NodeKind> kind;
    sample_nodes(body, lo, h_, n_, o, u, source, kind);
    interior_ = o.source_radius > 0;
    if (interior_ && std::count(kind.begin(), kind.end(), NodeKind::box) == 0)
        throw std::invalid_argument(
            "ExteriorPotential: the source ball holds no lattice node inside the body");
    const std::array<long long, 6> step = neighbour_offsets(n_);
    assemble_operator(kind, u, source, step, diag, rhs);
    unknowns_ = (long long)std::count(kind.begin(), kind.end(), NodeKind::free);
    const double margin = o.margin * longest;
    std::vector<double> start(kind.size(), 0.0);
    parallel_each(kind.size(), [&](size_t id) {
        if (kind[id] == NodeKind::free) start[id] = std::min(1.0, u[id] / margin);
    });
    const std::vector<double> x =
        solve_potential(kind, std::move(start), diag, rhs, step, o, iterations_);
    values_ = extend_into_body(kind, u, x, step, margin);
}

double ExteriorPotential::value(const Vec3& p) const {
    const Vec3 outside = (box_.lo - p).cwiseMax(p - box_.hi).cwiseMax(0.0);
    if (outside.squaredNorm() > 0)
        return interior_ ? value(p.cwiseMax(box_.lo).cwiseMin(box_.hi)) - outside.norm()
                         : 1 + outside.norm();
    const auto [c, t] = lattice_cell(box_, h_, n_, p);
    double v = 0;
    for_cell_nodes(n_, c, t, [&](size_t id, double w, const Vec3&) { v += w * values_[id]; });
    return v;
}

Vec3 ExteriorPotential::gradient(const Vec3& p) const {
    const Vec3 outside = (box_.lo - p).cwiseMax(p - box_.hi).cwiseMax(0.0);
    if (outside.squaredNorm() > 0) {
        const Vec3 away = p - p.cwiseMax(box_.lo).cwiseMin(box_.hi);
        return interior_ ? Vec3(-away.normalized()) : away.normalized();
    }
    const auto [c, t] = lattice_cell(box_, h_, n_, p);
    Vec3 g = Vec3::Zero();
    for_cell_nodes(n_, c, t, [&](size_t id, double, const Vec3& dw) { g += values_[id] * dw; });
    return g / h_;
}

HarmonicDirections::HarmonicDirections(const ImplicitFunction& body,
                                       const std::function<Vec3(const Vec3&)>& on_body,
                                       const Vec3& centre, const ExteriorPotentialOptions& o)
    : centre_(centre) {
    if (o.source_radius > 0)
        throw std::invalid_argument("HarmonicDirections: exterior only (source_radius must be 0)");
    const Lattice lattice = make_lattice(body, o);
    h_ = lattice.h;
    n_ = lattice.n;
    box_ = lattice.box;
    std::vector<double> u, source, diag, unit;
    std::vector<NodeKind> kind;
    sample_nodes(body, box_.lo, h_, n_, o, u, source, kind);
    const std::array<long long, 6> step = neighbour_offsets(n_);
    assemble_operator(kind, u, source, step, diag, unit);
    const size_t count = kind.size();
    const auto radial = [&](const Vec3& x) -> Vec3 {
        const Vec3 d = x - centre;
        return d.norm() > 0 ? Vec3(d.normalized()) : Vec3(Vec3::UnitX());
    };
    // Each free node's right side: its neighbours' data across the wall (at the crossing, by
    // the same rule as the coupling) and on the box.
    std::vector<Vec3> rhs(count, Vec3::Zero());
    parallel_each(count, [&](size_t id) {
        if (kind[id] != NodeKind::free) return;
        const Vec3 x = lattice.node(id);
        for (long long s : step) {
            const size_t m = size_t((long long)id + s);
            if (kind[m] == NodeKind::body) {
                const double t = u[id] / (u[id] - u[m]);
                rhs[id] += on_body(x + std::clamp(t, 0.0, 1.0) * (lattice.node(m) - x)) /
                           std::max(min_theta, t);
            } else if (kind[m] == NodeKind::box) {
                rhs[id] += radial(lattice.node(m));
            }
        }
    });
    values_.assign(count, Vec3::Zero());
    for (int c = 0; c < 3; ++c) {
        std::vector<double> b(count, 0.0), start(count, 0.0);
        parallel_each(count, [&](size_t id) {
            if (kind[id] != NodeKind::free) return;
            b[id] = rhs[id][c];
            start[id] = radial(lattice.node(id))[c];
        });
        int iterations = 0;
        const std::vector<double> x =
            solve_potential(kind, std::move(start), diag, b, step, o, iterations);
        iterations_ = std::max(iterations_, iterations);
        parallel_each(count, [&](size_t id) {
            if (kind[id] == NodeKind::free) values_[id][c] = x[id];
        });
    }
    // The box's nodes, and the body's nodes next to free ones (the only ones interpolation
    // outside the body reaches).
    parallel_each(count, [&](size_t id) {
        if (kind[id] == NodeKind::box) values_[id] = radial(lattice.node(id));
        if (kind[id] != NodeKind::body) return;
        const int i = int(id % n_[0]), j = int((id / n_[0]) % n_[1]),
                  k = int(id / (size_t(n_[0]) * n_[1]));
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int a = i + di, b = j + dj, e = k + dk;
                    if (a < 0 || b < 0 || e < 0 || a >= n_[0] || b >= n_[1] || e >= n_[2]) continue;
                    if (kind[a + n_[0] * (size_t(b) + size_t(n_[1]) * e)] != NodeKind::free)
                        continue;
                    values_[id] = on_body(lattice.node(id));
                    return;
                }
    });
}

Vec3 HarmonicDirections::value(const Vec3& p) const {
    const Vec3 outside = (box_.lo - p).cwiseMax(p - box_.hi).cwiseMax(0.0);
    if (outside.squaredNorm() > 0) return (p - centre_).normalized();
    const auto [c, t] = lattice_cell(box_, h_, n_, p);
    Vec3 v = Vec3::Zero();
    for_cell_nodes(n_, c, t, [&](size_t id, double w, const Vec3&) { v += w * values_[id]; });
    return v;
}

Mat3 HarmonicDirections::jacobian(const Vec3& p) const {
    const Vec3 outside = (box_.lo - p).cwiseMax(p - box_.hi).cwiseMax(0.0);
    if (outside.squaredNorm() > 0) return Mat3::Zero();
    const auto [c, t] = lattice_cell(box_, h_, n_, p);
    Mat3 J = Mat3::Zero();
    for_cell_nodes(n_, c, t,
                   [&](size_t id, double, const Vec3& dw) { J += values_[id] * dw.transpose(); });
    return J / h_;
}

}  // namespace hexmesh

#include "untangle/pcg.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "hexmesh/core/parallel_sum.h"

namespace hexmesh::untangle {

namespace {

constexpr size_t grain = 2048;

}  // namespace

double dot(const VertexVector& a, const VertexVector& b) {
    return deterministic_sum(a.size(), grain, [&](size_t i) { return a[i].dot(b[i]); });
}

namespace {

// The CG loop; precondition(r, z) sets z = M^-1 r and returns r . z. Per iteration, besides
// the product and the preconditioner: one pass for p . Ap, one that updates x and r and
// sums r . r, one for p.
template <class Precondition>
PcgResult pcg(const LinearOperator& apply_a, Precondition&& precondition, const VertexVector& b,
              VertexVector& x, double tolerance, int max_iterations) {
    const size_t n = b.size();
    x.assign(n, Vec3::Zero());
    VertexVector r = b, z(n), p(n), ap(n);
    const double b_norm = std::sqrt(dot(b, b));
    PcgResult result;
    if (b_norm == 0) return result;
    double rz = precondition(r, z);
    p = z;
    for (int it = 0; it < max_iterations; ++it) {
        apply_a(p, ap);
        const double curvature = dot(p, ap);
        if (!(curvature > 0)) break;
        const double alpha = rz / curvature;
        const double rr = deterministic_sum(n, grain, [&](size_t i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
            return r[i].squaredNorm();
        });
        result.iterations = it + 1;
        result.relative_residual = std::sqrt(rr) / b_norm;
        if (result.relative_residual <= tolerance) break;
        const double rz_next = precondition(r, z);
        const double beta = rz_next / rz;
        rz = rz_next;
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                          [&](const tbb::blocked_range<size_t>& range) {
                              for (size_t i = range.begin(); i != range.end(); ++i)
                                  p[i] = z[i] + beta * p[i];
                          });
    }
    return result;
}

}  // namespace

PcgResult solve_pcg(const LinearOperator& apply_a, const LinearOperator& precondition,
                    const VertexVector& b, VertexVector& x, double tolerance, int max_iterations) {
    return pcg(
        apply_a,
        [&](const VertexVector& r, VertexVector& z) {
            if (precondition)
                precondition(r, z);
            else
                z = r;
            return dot(r, z);
        },
        b, x, tolerance, max_iterations);
}

PcgResult solve_pcg(const LinearOperator& apply_a, const BlockInverse& precondition,
                    const VertexVector& b, VertexVector& x, double tolerance, int max_iterations) {
    return pcg(
        apply_a,
        [&](const VertexVector& r, VertexVector& z) {
            z.resize(r.size());
            return deterministic_sum(r.size(), grain, [&](size_t i) {
                z[i] = (precondition[i] * r[i].cast<float>()).cast<double>();
                return r[i].dot(z[i]);
            });
        },
        b, x, tolerance, max_iterations);
}

}  // namespace hexmesh::untangle

#include "untangle/pcg.h"

#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace hexmesh::untangle {

double dot(const VertexVector& a, const VertexVector& b) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<size_t>(0, a.size(), 2048), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double s) {
            for (size_t i = r.begin(); i != r.end(); ++i) s += a[i].dot(b[i]);
            return s;
        },
        [](double x, double y) { return x + y; }, tbb::simple_partitioner());
}

namespace {

// y += alpha x, in parallel.
void axpy(double alpha, const VertexVector& x, VertexVector& y) {
    tbb::parallel_for(size_t(0), x.size(), [&](size_t i) { y[i] += alpha * x[i]; });
}

}  // namespace

PcgResult solve_pcg(const LinearOperator& apply_a, const LinearOperator& precondition,
                    const VertexVector& b, VertexVector& x, double tolerance, int max_iterations) {
    const size_t n = b.size();
    x.assign(n, Vec3::Zero());
    VertexVector r = b, z(n), p(n), ap(n);
    const double b_norm = std::sqrt(dot(b, b));
    PcgResult result;
    if (b_norm == 0) return result;
    if (precondition) precondition(r, z); else z = r;
    p = z;
    double rz = dot(r, z);
    for (int it = 0; it < max_iterations; ++it) {
        apply_a(p, ap);
        const double curvature = dot(p, ap);
        if (!(curvature > 0)) break;
        const double alpha = rz / curvature;
        axpy(alpha, p, x);
        axpy(-alpha, ap, r);
        result.iterations = it + 1;
        result.relative_residual = std::sqrt(dot(r, r)) / b_norm;
        if (result.relative_residual <= tolerance) break;
        if (precondition) precondition(r, z); else z = r;
        const double rz_next = dot(r, z);
        const double beta = rz_next / rz;
        rz = rz_next;
        tbb::parallel_for(size_t(0), n, [&](size_t i) { p[i] = z[i] + beta * p[i]; });
    }
    return result;
}

}  // namespace hexmesh::untangle

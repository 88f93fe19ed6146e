// Minimizer: Newton (assembled or matrix-free) and L-BFGS directions inside the allowed
// bases, and the descent steps at a fixed eps.
#include "untangle/minimizer.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <cmath>

#include "untangle/constraints.h"
#include "untangle/pcg.h"

namespace hexmesh::untangle {
namespace {

// 1 for the directions a vertex may not move in (zero columns of its basis), else 0: added
// on the diagonal so the reduced system stays non-singular and leaves them at zero.
Vec3 locked_mask(const Mat3& basis) {
    Vec3 m;
    for (int c = 0; c < 3; ++c) m[c] = basis.col(c).squaredNorm() > 0 ? 0.0 : 1.0;
    return m;
}

double max_norm(const std::vector<Vec3>& v) {
    double m = 0;
    for (const Vec3& x : v) m = std::max(m, x.norm());
    return m;
}

// Diagonal shift lambda * active + locked mask, with lambda tiny against the mean diagonal.
struct DiagonalShift {
    std::vector<Vec3> shift;
    DiagonalShift(const std::vector<Mat3>& basis, const std::vector<Mat3>& reduced_diagonal) {
        double trace = 0;
        for (const Mat3& d : reduced_diagonal) trace += d.trace();
        const double lambda = 1e-9 * (trace > 0 ? trace / (3.0 * reduced_diagonal.size()) : 1.0);
        shift.resize(basis.size());
        for (size_t a = 0; a < basis.size(); ++a) {
            const Vec3 locked = locked_mask(basis[a]);
            shift[a] = locked + lambda * (Vec3::Ones() - locked);
        }
    }
};

// M^-1 per vertex from the reduced diagonal blocks (already shifted): their inverses (block
// Jacobi) or the inverses of their diagonals (Jacobi).
BlockInverse diagonal_preconditioner(Preconditioner kind, const std::vector<Mat3>& diagonal) {
    BlockInverse inverse(diagonal.size());
    tbb::parallel_for(size_t(0), diagonal.size(), [&](size_t a) {
        const Mat3 m = kind == Preconditioner::jacobi
                           ? Mat3(diagonal[a].diagonal().cwiseInverse().asDiagonal())
                           : Mat3(diagonal[a].inverse());
        inverse[a] = m.cast<float>();
    });
    return inverse;
}

// Incomplete Cholesky of the whole reduced matrix (both triangles from the stored upper
// one), through Eigen.
LinearOperator incomplete_cholesky(const BlockMatrix& r) {
    const Id n = 3 * r.rows();
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(9 * r.col.size());
    for (Id a = 0; a < r.rows(); ++a)
        for (Id m = r.row_start[a]; m < r.row_start[a + 1]; ++m)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    if (r.block[m](i, j) != 0) {
                        entries.emplace_back(3 * a + i, 3 * r.col[m] + j, r.block[m](i, j));
                        if (r.col[m] != a)
                            entries.emplace_back(3 * r.col[m] + j, 3 * a + i, r.block[m](i, j));
                    }
    Eigen::SparseMatrix<double> a(n, n);
    a.setFromTriplets(entries.begin(), entries.end());
    auto ic = std::make_shared<Eigen::IncompleteCholesky<double>>(a);
    return [ic, n](const VertexVector& in, VertexVector& out) {
        const Eigen::Map<const Eigen::VectorXd> b(in[0].data(), n);
        const Eigen::VectorXd x = ic->solve(b);
        out.resize(in.size());
        Eigen::Map<Eigen::VectorXd>(out[0].data(), n) = x;
    };
}

// The Hessian h into the bases of the allowed directions: block (a, b) becomes
// basis_a^T h_ab basis_b (nothing to do between two interior vertices).
void to_bases(const std::vector<VertexKind>& kinds, const std::vector<Mat3>& basis,
              BlockMatrix& h) {
    tbb::parallel_for(Id(0), h.rows(), [&](Id a) {
        for (Id m = h.row_start[a]; m < h.row_start[a + 1]; ++m) {
            const Id b = h.col[m];
            if (kinds[a] == VertexKind::interior && kinds[b] == VertexKind::interior) continue;
            h.block[m] =
                (basis[a].transpose() * h.block[m].cast<double>() * basis[b]).cast<float>();
        }
    });
}

// Solves h reduced = rhs one coordinate at a time (only the couplings between coordinate c
// of the vertices), each by conjugate gradients with Jacobi preconditioning unless `options`
// say none. Returns the CG iterations of the three solves.
int solve_by_coordinate(const BlockMatrix& h, const std::vector<Mat3>& diagonal,
                        const std::vector<Vec3>& rhs, const SolverOptions& options,
                        std::vector<Vec3>& reduced) {
    const size_t n = rhs.size();
    int iterations = 0;
    std::fill(reduced.begin(), reduced.end(), Vec3::Zero());
    for (int c = 0; c < 3; ++c) {
        std::vector<Vec3> b(n, Vec3::Zero()), xc;
        for (size_t a = 0; a < n; ++a) b[a][c] = rhs[a][c];
        const LinearOperator apply = [&, c](const VertexVector& v, VertexVector& out) {
            h.multiply(v, out, c);
        };
        const LinearOperator jacobi = [&, c](const VertexVector& r, VertexVector& z) {
            z.assign(r.size(), Vec3::Zero());
            for (size_t a = 0; a < r.size(); ++a) z[a][c] = r[a][c] / diagonal[a](c, c);
        };
        const PcgResult res = solve_pcg(
            apply, options.preconditioner == Preconditioner::none ? LinearOperator{} : jacobi, b,
            xc, options.cg_tolerance, options.cg_max_iterations);
        iterations += res.iterations;
        for (size_t a = 0; a < n; ++a) reduced[a][c] = xc[a][c];
    }
    return iterations;
}

}  // namespace

Minimizer::Minimizer(const Problem& problem, const Assembly& assembly, const SolverOptions& options)
    : problem_(problem), assembly_(assembly), options_(options) {}

double Minimizer::newton_direction(const std::vector<Vec3>& x, const EnergyParams& p,
                                   const std::vector<Mat3>& basis, std::vector<Vec3>& d,
                                   int& iterations) {
    const size_t n = x.size();
    std::vector<Vec3> g;
    std::vector<Mat3> diagonal;
    const bool matrix_free = options_.matrix_free && options_.method == Method::newton_cg;
    double f;
    if (matrix_free) {
        f = assembly_.diagonal_hessian(x, p, g, diagonal);
    } else {
        if (hessian_.col.empty()) hessian_ = assembly_.empty_hessian();
        f = assembly_.hessian(x, p, g, hessian_);
        to_bases(problem_.kinds, basis, hessian_);
        diagonal.resize(n);
        for (size_t a = 0; a < n; ++a)
            diagonal[a] = hessian_.block[hessian_.row_start[a]].cast<double>();
    }
    if (!std::isfinite(f)) return f;
    if (matrix_free)
        for (size_t a = 0; a < n; ++a) diagonal[a] = basis[a].transpose() * diagonal[a] * basis[a];
    const DiagonalShift shift(basis, diagonal);
    for (size_t a = 0; a < n; ++a) diagonal[a] += shift.shift[a].asDiagonal();
    if (!matrix_free)
        for (size_t a = 0; a < n; ++a)
            hessian_.block[hessian_.row_start[a]] = diagonal[a].cast<float>();

    std::vector<Vec3> rhs(n), reduced(n);
    for (size_t a = 0; a < n; ++a) rhs[a] = -(basis[a].transpose() * g[a]);

    if (options_.method == Method::coordinate_split) {
        iterations += solve_by_coordinate(hessian_, diagonal, rhs, options_, reduced);
    } else {
        LinearOperator apply;
        if (matrix_free) {
            apply = [&](const VertexVector& v, VertexVector& out) {
                std::vector<Vec3> w(n), hw;
                for (size_t a = 0; a < n; ++a) w[a] = basis[a] * v[a];
                assembly_.hessian_product(x, p, w, hw);
                out.resize(n);
                for (size_t a = 0; a < n; ++a)
                    out[a] = basis[a].transpose() * hw[a] + shift.shift[a].cwiseProduct(v[a]);
            };
        } else {
            apply = [&](const VertexVector& v, VertexVector& out) { hessian_.multiply(v, out); };
        }
        const Preconditioner kind = options_.preconditioner;
        PcgResult solved;
        if (kind == Preconditioner::incomplete_cholesky && !matrix_free)
            solved = solve_pcg(apply, incomplete_cholesky(hessian_), rhs, reduced,
                               options_.cg_tolerance, options_.cg_max_iterations);
        else if (kind == Preconditioner::none)
            solved = solve_pcg(apply, LinearOperator{}, rhs, reduced, options_.cg_tolerance,
                               options_.cg_max_iterations);
        else  // incomplete Cholesky needs the matrix: block Jacobi without one
            solved = solve_pcg(
                apply,
                diagonal_preconditioner(
                    kind == Preconditioner::jacobi ? kind : Preconditioner::block_jacobi, diagonal),
                rhs, reduced, options_.cg_tolerance, options_.cg_max_iterations);
        iterations += solved.iterations;
    }
    d.resize(n);
    for (size_t a = 0; a < n; ++a) d[a] = basis[a] * reduced[a];
    return f;
}

double Minimizer::lbfgs_direction(const std::vector<Vec3>& x, const EnergyParams& p,
                                  const std::vector<Mat3>& basis, std::vector<Vec3>& d) {
    const size_t n = x.size();
    std::vector<Vec3> g;
    const double f = assembly_.gradient(x, p, g);
    if (!std::isfinite(f)) return f;
    std::vector<Vec3> q(n);
    for (size_t a = 0; a < n; ++a) q[a] = basis[a] * (basis[a].transpose() * g[a]);
    if (!last_x_.empty()) {
        std::vector<Vec3> s(n), y(n);
        for (size_t a = 0; a < n; ++a) s[a] = x[a] - last_x_[a], y[a] = q[a] - last_gradient_[a];
        const double sy = dot(s, y);
        if (sy > 1e-12 * std::sqrt(dot(s, s) * dot(y, y))) {
            history_.emplace_back(std::move(s), std::move(y));
            if (int(history_.size()) > options_.lbfgs_history) history_.pop_front();
        }
    }
    last_x_ = x;
    last_gradient_ = q;
    d = q;
    std::vector<double> alpha(history_.size());
    for (int i = int(history_.size()) - 1; i >= 0; --i) {
        const auto& [s, y] = history_[i];
        alpha[i] = dot(s, d) / dot(y, s);
        for (size_t a = 0; a < n; ++a) d[a] -= alpha[i] * y[a];
    }
    double gamma;
    if (history_.empty()) {
        const double m = max_norm(q);
        gamma = m > 0 ? problem_.length_scale / m : 1.0;
    } else {
        const auto& [s, y] = history_.back();
        gamma = dot(s, y) / dot(y, y);
    }
    for (Vec3& v : d) v *= gamma;
    for (size_t i = 0; i < history_.size(); ++i) {
        const auto& [s, y] = history_[i];
        const double beta = dot(y, d) / dot(y, s);
        for (size_t a = 0; a < n; ++a) d[a] += (alpha[i] - beta) * s[a];
    }
    for (size_t a = 0; a < n; ++a) d[a] = -(basis[a] * (basis[a].transpose() * d[a]));
    if (!(dot(d, q) < 0)) {  // not a descent direction: restart from the scaled gradient
        history_.clear();
        const double m = max_norm(q);
        for (size_t a = 0; a < n; ++a) d[a] = -(m > 0 ? problem_.length_scale / m : 1.0) * q[a];
    }
    return f;
}

double Minimizer::direction(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& d,
                            int& linear_iterations) {
    const std::vector<Mat3> basis = movement_bases(problem_, x);
    const size_t n = x.size();
    switch (options_.method) {
        case Method::explicit_gradient: {
            std::vector<Vec3> g;
            const double f = assembly_.gradient(x, p, g);
            d.resize(n);
            for (size_t a = 0; a < n; ++a) d[a] = -(basis[a] * (basis[a].transpose() * g[a]));
            const double m = max_norm(d);
            if (m > 0)
                for (Vec3& v : d) v *= problem_.length_scale / m;
            return f;
        }
        case Method::block_diagonal: {
            std::vector<Vec3> g;
            std::vector<Mat3> diagonal;
            const double f = assembly_.diagonal_hessian(x, p, g, diagonal);
            for (size_t a = 0; a < n; ++a)
                diagonal[a] = basis[a].transpose() * diagonal[a] * basis[a];
            const DiagonalShift shift(basis, diagonal);
            d.resize(n);
            for (size_t a = 0; a < n; ++a) {
                const Mat3 r = diagonal[a] + Mat3(shift.shift[a].asDiagonal());
                d[a] = -(basis[a] * r.ldlt().solve(basis[a].transpose() * g[a]));
            }
            return f;
        }
        case Method::coordinate_split:
        case Method::newton_cg:
            return newton_direction(x, p, basis, d, linear_iterations);
        case Method::lbfgs:
            return lbfgs_direction(x, p, basis, d);
    }
    return 0;
}

MinimizeOutcome Minimizer::minimize(std::vector<Vec3>& x, const EnergyParams& p, int max_steps,
                                    double tolerance,
                                    const std::function<bool(const std::vector<Vec3>&)>& done) {
    history_.clear();
    last_x_.clear();
    MinimizeOutcome out;
    out.energy = assembly_.energy(x, p);
    std::vector<Vec3> d, trial(x.size());
    for (int step = 0; step < max_steps; ++step) {
        const double f0 = direction(x, p, d, out.linear_iterations);
        if (!std::isfinite(f0)) break;
        double tau = 1, f = f0;
        bool accepted = false;
        for (int h = 0; h <= options_.max_halvings && !accepted; ++h, tau *= 0.5) {
            for (size_t a = 0; a < x.size(); ++a) trial[a] = x[a] + tau * d[a];
            project_constrained(problem_, trial);
            f = assembly_.energy(trial, p);
            ++out.trials;
            accepted = f < f0;
        }
        if (!accepted) {
            if (options_.method == Method::lbfgs && !history_.empty()) {
                history_.clear();
                last_x_.clear();
                continue;
            }
            break;
        }
        x.swap(trial);
        out.energy = f;
        ++out.steps;
        if (f0 - f <= tolerance * std::abs(f0) || (done && done(x))) break;
    }
    return out;
}

}  // namespace hexmesh::untangle

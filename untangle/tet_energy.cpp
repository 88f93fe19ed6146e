#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "hexmesh/core/reference_hex.h"

#include "untangle/regularization.h"

namespace hexmesh::untangle {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

Mat3 edge_matrix(const Mat34& y) {
    Mat3 q;
    q << y.col(1) - y.col(0), y.col(2) - y.col(0), y.col(3) - y.col(0);
    return q;
}

// Cofactor matrix: d det / d S, well defined at det = 0.
Mat3 cofactor(const Mat3& s) {
    Mat3 c;
    c.col(0) = s.col(1).cross(s.col(2));
    c.col(1) = s.col(2).cross(s.col(0));
    c.col(2) = s.col(0).cross(s.col(1));
    return c;
}

// x^(-1/3) for x > 0, to about one ulp, without a library call or a division: a first
// guess from the bits of x (within 3.5 %), then three steps y <- y (1 + r/3 + 2 r^2/9),
// r = 1 - x y^3 (the series of (1 - r)^(-1/3), cubically convergent). Outside the normal
// range (or NaN) it falls back on the library.
double inverse_cbrt(double x) {
    if (!(x > 1e-300 && x < 1e300)) return 1 / std::cbrt(x);
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    bits = 0x553eeeeeeeeef000ull - bits / 3;
    double y;
    std::memcpy(&y, &bits, sizeof y);
    for (int k = 0; k < 3; ++k) {
        const double r = 1 - x * y * y * y;
        y *= 1 + r * (1.0 / 3 + r * (2.0 / 9));
    }
    return y;
}

// phi as a function of I = tr(S^T S) and d = det S, with the partial derivatives needed.
struct Invariants {
    double value, f_i, f_d, f_dd, f_id;
};

Invariants phi(double i, double d, double v0, const EnergyParams& p, bool second) {
    const double eps = p.eps, theta = p.theta;
    // chi(d, eps) and its first two derivatives, one square root for all three.
    double x = d, x1 = 1, x2 = 0;
    if (eps > 0) {
        const double r = regularization_radius(d, eps);
        x = chi(d, eps, r);
        x1 = chi_derivative(d, eps, r);
        x2 = 0.5 * eps * eps / (r * r * r);
    }
    // Powers of chi from y = chi^(-1/3): chi^(-2/3) = y^2, 1 / chi = y^3.
    const double y = inverse_cbrt(x), y2 = y * y, y3 = y2 * y, y5 = y3 * y2, inv_v0 = 1 / v0;
    const double mu = 0.5 * (v0 * y3 + x * inv_v0), mu1 = 0.5 * (inv_v0 - v0 * y3 * y3);
    const double nu = i * y2 / 3, nu1 = -2.0 / 9 * i * y5;
    Invariants f{};
    f.value = theta * mu + (1 - theta) * nu;
    f.f_i = (1 - theta) / 3 * y2;
    f.f_d = (theta * mu1 + (1 - theta) * nu1) * x1;
    if (second) {
        const double mu2 = v0 * y3 * y3 * y3, nu2 = 10.0 / 27 * i * y5 * y3;
        const double nu1i = -2.0 / 9 * y5;
        f.f_dd = (theta * mu2 + (1 - theta) * nu2) * x1 * x1 + (theta * mu1 + (1 - theta) * nu1) * x2;
        f.f_id = (1 - theta) * nu1i * x1;
    }
    return f;
}


// Signed SVD S = U diag(sigma) V^T with U, V rotations (sigma[2] < 0 when det S < 0), from
// the closed-form eigensystem of S^T S: V its eigenvectors (largest first), U by
// Gram-Schmidt on S V, sigma the diagonal of U^T S V. Accurate where the singular values are
// apart; where they nearly coincide any basis of their space is a valid choice.
void signed_svd(const Mat3& s, Mat3& u, Vec3& sigma, Mat3& v) {
    Eigen::SelfAdjointEigenSolver<Mat3> eigen;
    eigen.computeDirect(s.transpose() * s);
    v = eigen.eigenvectors().rowwise().reverse();  // eigenvalues ascend: largest first
    if (v.determinant() < 0) v.col(2) *= -1;
    const Mat3 sv = s * v;
    auto unit_or = [](const Vec3& w, const Vec3& fallback) {
        const double n = w.norm();
        return n > 1e-300 ? Vec3(w / n) : fallback;
    };
    u.col(0) = unit_or(sv.col(0), Vec3::UnitX());
    const Vec3 any_normal = u.col(0).unitOrthogonal();
    u.col(1) = unit_or(sv.col(1) - u.col(0).dot(sv.col(1)) * u.col(0), any_normal);
    u.col(2) = u.col(0).cross(u.col(1));
    for (int k = 0; k < 3; ++k) sigma[k] = u.col(k).dot(sv.col(k));
}

// phi at S and its derivatives; false when eps = 0 and det S <= 0, where the barrier is
// infinite.
template <bool second>
bool phi_at(const Mat3& s, double v0, const EnergyParams& p, Invariants& f) {
    const double d = s.determinant();
    if (p.eps <= 0 && d <= 0) return false;
    f = phi(s.squaredNorm(), d, v0, p, second);
    return true;
}

// d phi / d S.
Mat3 phi_gradient(const Mat3& s, const Invariants& f) { return 2 * f.f_i * s + f.f_d * cofactor(s); }

// S = Q H^-1, the derivatives of phi at S and the vertex gradient; false (nothing set
// beyond s) when eps = 0 and det S <= 0, where the barrier is infinite.
template <bool second>
bool evaluate(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat3& s, Invariants& f,
              Mat34& grad) {
    s = edge_matrix(y) * t.inverse;
    if (!phi_at<second>(s, t.v0, p, f)) return false;
    const Mat3 dq = t.weight * phi_gradient(s, f) * t.inverse.transpose();
    grad.col(0) = -dq.rowwise().sum();
    grad.rightCols<3>() = dq;
    return true;
}

// Per corner tet c of a hex, the axis of each of its three edges (its target's diagonal).
constexpr std::array<std::array<int, 3>, 8> corner_axes = [] {
    std::array<std::array<int, 3>, 8> axes{};
    for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 3; ++k) axes[c][k] = hex_edge_axis(hex_corner_tets[c][0], hex_corner_tets[c][k + 1]);
    return axes;
}();

}  // namespace

double tet_det(const Mat34& y, const TetTarget& t) {
    return (edge_matrix(y) * t.inverse).determinant();
}

double tet_energy(const Mat34& y, const TetTarget& t, const EnergyParams& p) {
    const Mat3 s = edge_matrix(y) * t.inverse;
    const double d = s.determinant();
    if (p.eps <= 0 && d <= 0) return infinity;
    return t.weight * phi(s.squaredNorm(), d, t.v0, p, false).value;
}

double tet_energy_gradient(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat34& grad) {
    Mat3 s;
    Invariants f;
    return evaluate<false>(y, t, p, s, f, grad) ? t.weight * f.value : infinity;
}

double tet_energy_hessian(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat34& grad,
                          Mat12& hess, bool project_psd) {
    Mat3 s;
    Invariants f;
    if (!evaluate<true>(y, t, p, s, f, grad)) return infinity;

    // Analytic eigensystem of the 9 x 9 Hessian in S of an isotropic energy f(I, det S)
    // (Smith, de Goes, Kim 2019): with the signed SVD S = U diag(sigma) V^T, the twists
    // U T_ij V^T and flips U F_ij V^T are eigenvectors with eigenvalues 2 f_I +- f_d sigma_k,
    // and the scalings U diag(v) V^T span the rest, where v are the eigenvectors of the 3 x 3
    // Hessian of f(sum sigma^2, prod sigma) in sigma. Each mode q contributes
    // lambda (D^T q)(D^T q)^T to the 12 x 12 Hessian, with (D^T q)_a = U M V^T g_a.
    Mat3 u, v;
    Vec3 sigma;
    signed_svd(s, u, sigma, v);
    const Vec3 d_i(sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]);
    Mat3 a;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a(i, j) = 2 * f.f_id * (sigma[i] * d_i[j] + sigma[j] * d_i[i]) + f.f_dd * d_i[i] * d_i[j] +
                      (i == j ? 2 * f.f_i : f.f_d * sigma[3 - i - j]);
    // The modes act on vertices 1..3 through the rows of H^-1; vertex 0 moves by minus their
    // sum, so its blocks follow from the 9 x 9 part. With g_a the columns of H^-T, the mode
    // U M V^T has the vertex vector (U M V^T g_a)_a, and U E_ij V^T g_a = u_i (V^T g_a)_j:
    // every mode is a combination of the outer products p_ij = u_i (row j of V^T H^-T).
    const Mat3 vg = v.transpose() * t.inverse.transpose();  // column a - 1: V^T g_a
    using Vec9 = Eigen::Matrix<double, 9, 1>;
    const auto outer = [&](int i, int j) {
        Vec9 w;
        for (int a = 0; a < 3; ++a) w.segment<3>(3 * a) = u.col(i) * vg(j, a);
        return w;
    };
    // h9 = sum over the kept modes of lambda w w^T: its upper triangle by rank-one updates,
    // then mirrored.
    Eigen::Matrix<double, 9, 9> h9 = Eigen::Matrix<double, 9, 9>::Zero();
    // The element weight is applied to the eigenvalues (and to a) rather than to the result.
    const auto add_mode = [&](const Vec9& w, double l) {
        if (project_psd && l <= 0) return;
        for (int j = 0; j < 9; ++j) {
            const double lw = t.weight * l * w[j];
            for (int i = 0; i <= j; ++i) h9(i, j) += lw * w[i];
        }
    };
    // Scalings: w = sum_m e_m p_mm over an eigenvector e of a; when a is positive definite
    // nothing is clamped and the three of them sum to sum_mn a_mn p_mm p_nn^T, with no
    // eigensystem to compute.
    Eigen::Matrix<double, 9, 3> diagonal_modes;
    for (int m = 0; m < 3; ++m) diagonal_modes.col(m) = outer(m, m);
    const bool definite = a(0, 0) > 0 && a(0, 0) * a(1, 1) - a(0, 1) * a(0, 1) > 0 && a.determinant() > 0;
    if (definite || !project_psd) {
        const Eigen::Matrix<double, 9, 3> wa = diagonal_modes * (t.weight * a);
        for (int j = 0; j < 9; ++j)
            for (int i = 0; i <= j; ++i) h9(i, j) += wa.row(i).dot(diagonal_modes.row(j));
    } else {
        Eigen::SelfAdjointEigenSolver<Mat3> scaling;
        scaling.computeDirect(a);
        for (int m = 0; m < 3; ++m) add_mode(diagonal_modes * scaling.eigenvectors().col(m), scaling.eigenvalues()[m]);
    }
    // Twists (u_i v_j^T - u_j v_i^T) / sqrt 2 and flips (the same with +).
    const double r = std::sqrt(0.5);
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const Vec9 pij = outer(i, j), pji = outer(j, i);
        add_mode(r * (pij - pji), 2 * f.f_i + f.f_d * sigma[k]);
        add_mode(r * (pij + pji), 2 * f.f_i - f.f_d * sigma[k]);
    }
    h9.triangularView<Eigen::StrictlyLower>() = h9.transpose();
    hess.bottomRightCorner<9, 9>() = h9;
    for (int b = 0; b < 3; ++b) {
        Mat3 column = Mat3::Zero();  // block (0, b + 1) = -sum_a block (a + 1, b + 1)
        for (int a = 0; a < 3; ++a) column -= h9.block<3, 3>(3 * a, 3 * b);
        hess.block<3, 3>(0, 3 + 3 * b) = column;
        hess.block<3, 3>(3 + 3 * b, 0) = column.transpose();
    }
    Mat3 corner = Mat3::Zero();
    for (int b = 0; b < 3; ++b) corner -= hess.block<3, 3>(0, 3 + 3 * b);
    hess.topLeftCorner<3, 3>() = corner;
    return t.weight * f.value;
}

double hex_energy(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad) {
    // Corner tet c has S = [y_a - y_c, y_b - y_c, y_d - y_c] diag(1 / edges along its axes):
    // scaled edge vectors, no matrix product; its gradient is d phi / d S scaled back.
    const Vec3 inverse = edges.cwiseInverse();
    const double weight = edges.prod() / 6;
    if (grad) grad->setZero();
    double total = 0;
    for (int c = 0; c < 8; ++c) {
        const auto& t = hex_corner_tets[c];
        Mat3 s;
        Vec3 scale;
        for (int k = 0; k < 3; ++k) {
            scale[k] = inverse[corner_axes[c][k]];
            s.col(k) = (y.col(t[k + 1]) - y.col(t[0])) * scale[k];
        }
        Invariants f;
        if (!phi_at<false>(s, 1, p, f)) return infinity;
        total += f.value;
        if (!grad) continue;
        const Mat3 dq = weight * phi_gradient(s, f) * scale.asDiagonal();
        for (int k = 0; k < 3; ++k) grad->col(t[k + 1]) += dq.col(k);
        grad->col(t[0]) -= dq.rowwise().sum();
    }
    return weight * total;
}

TetTarget regular_tet_target(double edge) {
    Mat3 h;
    h.col(0) = Vec3(1, 0, 0);
    h.col(1) = Vec3(0.5, std::sqrt(3.0) / 2, 0);
    h.col(2) = Vec3(0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3));
    h *= edge;
    return {h.inverse(), h.determinant() / 6, 1};
}

}  // namespace hexmesh::untangle

#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

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
    const double x23 = std::cbrt(x * x);  // chi^(2/3)
    const double mu = 0.5 * (v0 / x + x / v0), mu1 = 0.5 * (1 / v0 - v0 / (x * x));
    const double nu = i / (3 * x23), nu1 = -2.0 / 9 * i / (x23 * x);
    Invariants f{};
    f.value = theta * mu + (1 - theta) * nu;
    f.f_i = (1 - theta) / (3 * x23);
    f.f_d = (theta * mu1 + (1 - theta) * nu1) * x1;
    if (second) {
        const double mu2 = v0 / (x * x * x), nu2 = 10.0 / 27 * i / (x23 * x * x);
        const double nu1i = -2.0 / 9 / (x23 * x);
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

// S = Q H^-1, the derivatives of phi at S and the vertex gradient; false (nothing set
// beyond s) when eps = 0 and det S <= 0, where the barrier is infinite.
template <bool second>
bool evaluate(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat3& s, Invariants& f,
              Mat34& grad) {
    s = edge_matrix(y) * t.inverse;
    const double d = s.determinant();
    if (p.eps <= 0 && d <= 0) return false;
    f = phi(s.squaredNorm(), d, t.v0, p, second);
    const Mat3 dq = t.weight * (2 * f.f_i * s + f.f_d * cofactor(s)) * t.inverse.transpose();
    grad.col(0) = -dq.rowwise().sum();
    grad.rightCols<3>() = dq;
    return true;
}

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
    Eigen::SelfAdjointEigenSolver<Mat3> scaling;
    scaling.computeDirect(a);

    // The modes act on vertices 1..3 through the rows of H^-1; vertex 0 moves by minus their
    // sum, so its blocks follow from the 9 x 9 part: W Lambda W^T with W the 9 x 9 matrix
    // of the modes' vertex vectors.
    const Mat3 vg = v.transpose() * t.inverse.transpose();  // column a - 1: V^T g_a
    Eigen::Matrix<double, 9, 9> w;
    Eigen::Matrix<double, 9, 1> lambda;
    int modes = 0;
    auto add_mode = [&](const Mat3& m, double l) {
        if (project_psd && l <= 0) return;
        const Mat3 umvg = u * m * vg;
        for (int a = 0; a < 3; ++a) w.col(modes).segment<3>(3 * a) = umvg.col(a);
        lambda[modes++] = l;
    };
    for (int m = 0; m < 3; ++m) add_mode(scaling.eigenvectors().col(m).asDiagonal(), scaling.eigenvalues()[m]);
    const double r = std::sqrt(0.5);
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        Mat3 twist = Mat3::Zero(), flip = Mat3::Zero();
        twist(i, j) = r, twist(j, i) = -r;
        flip(i, j) = r, flip(j, i) = r;
        add_mode(twist, 2 * f.f_i + f.f_d * sigma[k]);
        add_mode(flip, 2 * f.f_i - f.f_d * sigma[k]);
    }
    Eigen::Matrix<double, 9, 9> h9;
    if (modes == 0) {
        h9.setZero();
    } else {
        const auto wm = w.leftCols(modes);
        h9.noalias() = wm * (lambda.head(modes).asDiagonal() * wm.transpose());
    }
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
    hess *= t.weight;
    return t.weight * f.value;
}

TetTarget regular_tet_target(double edge) {
    Mat3 h;
    h.col(0) = Vec3(1, 0, 0);
    h.col(1) = Vec3(0.5, std::sqrt(3.0) / 2, 0);
    h.col(2) = Vec3(0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3));
    h *= edge;
    return {h.inverse(), h.determinant() / 6, 1};
}

TetTarget box_corner_target(const Vec3& edges) {
    const Mat3 h = edges.asDiagonal();
    return {h.inverse(), h.determinant() / 6, 1};
}

}  // namespace hexmesh::untangle

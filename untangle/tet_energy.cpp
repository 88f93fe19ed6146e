#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
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
    const double x = eps > 0 ? chi(d, eps) : d;
    const double x1 = eps > 0 ? chi_derivative(d, eps) : 1.0;
    const double r = std::hypot(eps, d);
    const double x2 = eps > 0 ? 0.5 * eps * eps / (r * r * r) : 0.0;
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
    Eigen::JacobiSVD<Mat3> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 u = svd.matrixU(), v = svd.matrixV();
    Vec3 sigma = svd.singularValues();
    if (u.determinant() < 0) u.col(2) *= -1, sigma[2] *= -1;
    if (v.determinant() < 0) v.col(2) *= -1, sigma[2] *= -1;
    const Vec3 d_i(sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]);
    Mat3 a;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a(i, j) = 2 * f.f_id * (sigma[i] * d_i[j] + sigma[j] * d_i[i]) + f.f_dd * d_i[i] * d_i[j] +
                      (i == j ? 2 * f.f_i : f.f_d * sigma[3 - i - j]);
    Eigen::SelfAdjointEigenSolver<Mat3> scaling;
    scaling.computeDirect(a);

    Eigen::Matrix<double, 3, 4> g;  // columns: d(vec S)/d y_a factors (rows of H^-1)
    for (int k = 1; k < 4; ++k) g.col(k) = t.inverse.row(k - 1).transpose();
    g.col(0) = -(g.col(1) + g.col(2) + g.col(3));
    const Eigen::Matrix<double, 3, 4> vg = v.transpose() * g;
    hess.setZero();
    auto add_mode = [&](const Mat3& m, double lambda) {
        if (project_psd && lambda <= 0) return;
        const Mat3 um = u * m;
        Eigen::Matrix<double, 12, 1> w;
        for (int k = 0; k < 4; ++k) w.segment<3>(3 * k) = um * vg.col(k);
        hess.noalias() += lambda * w * w.transpose();
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

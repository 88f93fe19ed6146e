#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "untangle/regularization.h"

namespace hexmesh::untangle {
namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
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

// d vec(S) / d y (vec column-major, y vertex-major): S = Q H^-1 is linear in y.
Eigen::Matrix<double, 9, 12> s_jacobian(const Mat3& inv) {
    std::array<Eigen::RowVector3d, 4> g;
    for (int a = 1; a < 4; ++a) g[a] = inv.row(a - 1);
    g[0] = -(g[1] + g[2] + g[3]);
    Eigen::Matrix<double, 9, 12> D = Eigen::Matrix<double, 9, 12>::Zero();
    for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 3; ++c)
            for (int j = 0; j < 3; ++j) D(c + 3 * j, 3 * a + c) = g[a][j];
    return D;
}

constexpr int levi(int i, int j, int k) { return (i - j) * (j - k) * (k - i) / 2; }

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
    const Mat3 s = edge_matrix(y) * t.inverse;
    const double d = s.determinant();
    if (p.eps <= 0 && d <= 0) return infinity;
    const Invariants f = phi(s.squaredNorm(), d, t.v0, p, false);
    const Mat3 dq = t.weight * (2 * f.f_i * s + f.f_d * cofactor(s)) * t.inverse.transpose();
    grad.col(0) = -dq.rowwise().sum();
    grad.rightCols<3>() = dq;
    return t.weight * f.value;
}

double tet_energy_hessian(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat34& grad,
                          Mat12& hess, bool project_psd) {
    const Mat3 s = edge_matrix(y) * t.inverse;
    const double d = s.determinant();
    if (p.eps <= 0 && d <= 0) return infinity;
    const Invariants f = phi(s.squaredNorm(), d, t.v0, p, true);
    const Mat3 cof = cofactor(s);
    const Mat3 dq = t.weight * (2 * f.f_i * s + f.f_d * cof) * t.inverse.transpose();
    grad.col(0) = -dq.rowwise().sum();
    grad.rightCols<3>() = dq;

    const Vec9 sv = Eigen::Map<const Vec9>(s.data()), cv = Eigen::Map<const Vec9>(cof.data());
    Mat9 h = 2 * f.f_i * Mat9::Identity() + f.f_dd * cv * cv.transpose() +
             2 * f.f_id * (sv * cv.transpose() + cv * sv.transpose());
    // f_d times the Hessian of det: d cof_ij / d S_kl = eps_ikb eps_jld S_bd.
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            if (i == k) continue;
            const int b = 3 - i - k;
            for (int j = 0; j < 3; ++j)
                for (int l = 0; l < 3; ++l) {
                    if (j == l) continue;
                    const int dd = 3 - j - l;
                    h(i + 3 * j, k + 3 * l) += f.f_d * levi(i, k, b) * levi(j, l, dd) * s(b, dd);
                }
        }
    if (project_psd) {
        Eigen::SelfAdjointEigenSolver<Mat9> eig(h);
        const Vec9 lambda = eig.eigenvalues().cwiseMax(0.0);
        h = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
    }
    const Eigen::Matrix<double, 9, 12> D = s_jacobian(t.inverse);
    hess = t.weight * D.transpose() * h * D;
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

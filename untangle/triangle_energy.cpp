#include "untangle/triangle_energy.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "untangle/regularization.h"

namespace hexmesh::untangle {
namespace {

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

constexpr double infinity = std::numeric_limits<double>::infinity();

// Rows t1, t2 of a right-handed orthonormal frame (t1, t2, n / |n|).
Mat23 tangent_frame(const Vec3& n) {
    const Vec3 unit = n / n.norm();
    const Vec3 t1 = unit.unitOrthogonal();
    Mat23 p;
    p.row(0) = t1;
    p.row(1) = unit.cross(t1);
    return p;
}

// [y1 - y0, y2 - y0].
Eigen::Matrix<double, 3, 2> edge_matrix(const Mat3& y) {
    Eigen::Matrix<double, 3, 2> e;
    e << y.col(1) - y.col(0), y.col(2) - y.col(0);
    return e;
}

// phi as a function of I = tr(S^T S) and d = det S, with the partial derivatives needed.
struct Invariants {
    double value = 0, f_i = 0, f_d = 0, f_dd = 0, f_id = 0;
};

Invariants phi(double i, double d, double v0, const EnergyParams& p) {
    const double theta = p.theta;
    double x = d, x1 = 1, x2 = 0;  // chi(d, eps) and its derivatives in d
    if (p.eps > 0) {
        const double r = regularization_radius(d, p.eps);
        x = chi(d, p.eps, r);
        x1 = chi_derivative(d, p.eps, r);
        x2 = 0.5 * p.eps * p.eps / (r * r * r);
    }
    const double inv = 1 / x, inv2 = inv * inv, inv3 = inv2 * inv;
    const double mu = 0.5 * (v0 * inv + x / v0), mu1 = 0.5 * (1 / v0 - v0 * inv2), mu2 = v0 * inv3;
    const double nu = 0.5 * i * inv, nu1 = -0.5 * i * inv2, nu2 = i * inv3;
    Invariants f;
    f.value = theta * mu + (1 - theta) * nu;
    f.f_i = 0.5 * (1 - theta) * inv;
    f.f_d = (theta * mu1 + (1 - theta) * nu1) * x1;
    f.f_dd = (theta * mu2 + (1 - theta) * nu2) * x1 * x1 + (theta * mu1 + (1 - theta) * nu1) * x2;
    f.f_id = -0.5 * (1 - theta) * inv2 * x1;
    return f;
}

// d det S / d S.
Mat2 cofactor(const Mat2& s) {
    Mat2 c;
    c << s(1, 1), -s(1, 0), -s(0, 1), s(0, 0);
    return c;
}

// What every evaluation needs: the frame, S and phi's derivatives at S. False when the
// barrier is infinite (eps = 0, det S <= 0) or the value is not finite.
struct Evaluation {
    Mat23 frame;
    Mat2 s;
    Invariants f;
};

bool evaluate(const Mat3& y, const Vec3& n, const TriangleTarget& t, const EnergyParams& p,
              Evaluation& e, double& value) {
    e.frame = tangent_frame(n);
    e.s = e.frame * edge_matrix(y) * t.inverse;  // the same expression as triangle_det
    const double d = e.s.determinant();
    if (p.eps <= 0 && d <= 0) {
        value = infinity;
        return false;
    }
    e.f = phi(e.s.squaredNorm(), d, t.v0, p);
    value = t.weight * e.f.value;
    return std::isfinite(value);
}

// Column a: dE/dy_a from G = dphi/dS: w P^T G H^-T for vertices 1 and 2, minus their sum for 0.
void vertex_gradient(const Evaluation& e, const TriangleTarget& t, Mat3& grad) {
    const Mat2 g = 2 * e.f.f_i * e.s + e.f.f_d * cofactor(e.s);
    const Eigen::Matrix<double, 3, 2> dq =
        t.weight * e.frame.transpose() * g * t.inverse.transpose();
    grad.col(0) = -dq.rowwise().sum();
    grad.rightCols<2>() = dq;
}

}  // namespace

double triangle_det(const Mat3& y, const Vec3& n, const TriangleTarget& t) {
    return (tangent_frame(n) * edge_matrix(y) * t.inverse).determinant();
}

double triangle_energy(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                       const EnergyParams& p) {
    Evaluation e;
    double value;
    evaluate(y, n, t, p, e, value);
    return value;
}

double triangle_energy_gradient(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                                const EnergyParams& p, Mat3& grad) {
    Evaluation e;
    double value;
    if (evaluate(y, n, t, p, e, value)) vertex_gradient(e, t, grad);
    return value;
}

double triangle_energy_hessian(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                               const EnergyParams& p, Mat3& grad, Mat9& hess, bool project_psd) {
    Evaluation e;
    double value;
    if (!evaluate(y, n, t, p, e, value)) return value;
    vertex_gradient(e, t, grad);

    // Hessian of phi in vec(S) (column-major: s00, s10, s01, s11) from I and d:
    // 2 f_I Id + f_Id (dI dd^T + dd dI^T) + f_dd dd dd^T + f_d d2(det).
    const Invariants& f = e.f;
    const Vec4 di = 2 * Eigen::Map<const Vec4>(e.s.data());
    const Mat2 c = cofactor(e.s);
    const Vec4 dd = Eigen::Map<const Vec4>(c.data());
    Mat4 h = 2 * f.f_i * Mat4::Identity() + f.f_id * (di * dd.transpose() + dd * di.transpose()) +
             f.f_dd * dd * dd.transpose();
    h(0, 3) += f.f_d, h(3, 0) += f.f_d, h(1, 2) -= f.f_d, h(2, 1) -= f.f_d;
    if (project_psd) {
        Eigen::SelfAdjointEigenSolver<Mat4> eigen(h);
        if (eigen.eigenvalues()[0] < 0)
            h = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() *
                eigen.eigenvectors().transpose();
    }
    // d vec(S) / d y: entry (i + 2 j, 3 a + c) = P(i, c) g_a(j), g_a the row a - 1 of H^-1
    // (minus their sum for a = 0).
    Eigen::Matrix<double, 4, 9> jac;
    for (int a = 0; a < 3; ++a) {
        const Eigen::RowVector2d g = a == 0 ? Eigen::RowVector2d(-t.inverse.colwise().sum())
                                            : Eigen::RowVector2d(t.inverse.row(a - 1));
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) jac.block<1, 3>(i + 2 * j, 3 * a) = e.frame.row(i) * g[j];
    }
    hess = t.weight * jac.transpose() * h * jac;
    return value;
}

}  // namespace hexmesh::untangle

// The energy of one tetrahedron, its gradient and its (PSD-projected) Hessian, in scalar code;
// the hex corner tets in vector lanes are in untangle/tet_energy_lanes.cpp.
#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "untangle/regularization.h"
#include "untangle/signed_svd.h"

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

// The first guess of x^(-1/3) (within 3.5 %) from the bits of x > 0: the exponent and the
// leading mantissa bits divided by -3, i.e. 0x553eeeeeeeeef000 - bits / 3, with only the
// high 32 bits divided (hi / 3 = (hi * 0xAAAAAAAB) >> 33 exactly, hi < 2^31) so that the
// same integer arithmetic runs in vector lanes.
inline uint64_t inverse_cbrt_guess(uint64_t bits) {
    return 0x553eeeeeeeeef000ULL - ((((bits >> 32) * 0xAAAAAAABULL) >> 33) << 32);
}

// x^(-1/3) for x > 0, to about one ulp, without a library call or a division: the guess
// above, then three steps y <- y (1 + r/3 + 2 r^2/9), r = 1 - x y^3 (the series of
// (1 - r)^(-1/3), cubically convergent). Outside the normal range (or NaN) it falls back on
// the library.
double inverse_cbrt(double x) {
    if (!(x > 1e-300 && x < 1e300)) return 1 / std::cbrt(x);
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    bits = inverse_cbrt_guess(bits);
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
        f.f_dd =
            (theta * mu2 + (1 - theta) * nu2) * x1 * x1 + (theta * mu1 + (1 - theta) * nu1) * x2;
        f.f_id = (1 - theta) * nu1i * x1;
    }
    return f;
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
Mat3 phi_gradient(const Mat3& s, const Invariants& f) {
    return 2 * f.f_i * s + f.f_d * cofactor(s);
}

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

// The 16 vertex blocks (block (a, b) = d2E / dy_a dy_b) of the Hessian of
// E = weight phi(S), S = [y1 - y0, y2 - y0, y3 - y0] H^-1, with g = H^-T; its negative
// eigenvalues clamped to zero unless project_psd is false.
//
// The Hessian in S of an isotropic f(I, det S) has a closed-form eigensystem (Smith, de Goes,
// Kim 2019): with the signed SVD S = U diag(sigma) V^T, its modes are U C V^T with C = E_ij -
// E_ji (twists, eigenvalue 2 f_I + f_d sigma_k, k the third index), C = E_ij + E_ji (flips,
// 2 f_I - f_d sigma_k), both over sqrt 2, and C diagonal (scalings: the eigenvectors of
// the 3 x 3 Hessian `a` of f(sum sigma^2, prod sigma) in sigma). Vertex a >= 1 moves S by
// e_c g_a^T, so a mode moves it by U C x_a with x_a = V^T g_a, and summing
// lambda (U C x_a)(U C x_b)^T over the modes gives block (a, b) = U K_ab U^T with
//   K_ab = a+ o (x_a x_b^T) + B o (x_b x_a^T) + diag(A (x_a o x_b))
// (o: entrywise product), a+ = `a` clamped, and for i != j with k = 3 - i - j:
// B_ij = (lambda_flip - lambda_twist) / 2, A_ij = (lambda_flip + lambda_twist) / 2 (clamped).
// Vertex 0 moves S by minus the sum of the others: its blocks are minus sums.
void hessian_blocks(const Mat3& s, const Invariants& f, const Mat3& g, double weight,
                    bool project_psd, TetBlocks& blocks) {
    Mat3 u, v;
    Vec3 sigma;
    signed_svd(s, u, sigma, v);
    const Vec3 d_i(sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]);
    Mat3 a;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a(i, j) = 2 * f.f_id * (sigma[i] * d_i[j] + sigma[j] * d_i[i]) +
                      f.f_dd * d_i[i] * d_i[j] + (i == j ? 2 * f.f_i : f.f_d * sigma[3 - i - j]);
    const bool definite =
        a(0, 0) > 0 && a(0, 0) * a(1, 1) - a(0, 1) * a(0, 1) > 0 && a.determinant() > 0;
    Mat3 scaling;  // weight a+
    if (definite || !project_psd) {
        scaling = weight * a;
    } else {
        Eigen::SelfAdjointEigenSolver<Mat3> eigen;
        eigen.computeDirect(a);
        scaling = eigen.eigenvectors() * (weight * eigen.eigenvalues().cwiseMax(0.0)).asDiagonal() *
                  eigen.eigenvectors().transpose();
    }
    Mat3 pair = Mat3::Zero(), twist_flip = Mat3::Zero();  // weight A and weight B, zero diagonals
    for (int k = 0; k < 3; ++k) {
        double twist = 2 * f.f_i + f.f_d * sigma[k], flip = 2 * f.f_i - f.f_d * sigma[k];
        if (project_psd) twist = std::max(twist, 0.0), flip = std::max(flip, 0.0);
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        pair(i, j) = pair(j, i) = 0.5 * weight * (flip + twist);
        twist_flip(i, j) = twist_flip(j, i) = 0.5 * weight * (flip - twist);
    }
    const Mat3 x = v.transpose() * g;  // column a - 1: x_a
    for (int a1 = 0; a1 < 3; ++a1)
        for (int b1 = a1; b1 < 3; ++b1) {
            const Vec3 xa = x.col(a1), xb = x.col(b1);
            Mat3 k = scaling.cwiseProduct(xa * xb.transpose()) +
                     twist_flip.cwiseProduct(xb * xa.transpose());
            k.diagonal() += pair * xa.cwiseProduct(xb);
            blocks[a1 + 1][b1 + 1] = u * k * u.transpose();
            if (b1 != a1) blocks[b1 + 1][a1 + 1] = blocks[a1 + 1][b1 + 1].transpose();
        }
    blocks[0][0].setZero();
    for (int b = 1; b < 4; ++b) {
        blocks[0][b] = -(blocks[1][b] + blocks[2][b] + blocks[3][b]);
        blocks[b][0] = blocks[0][b].transpose();
        blocks[0][0] -= blocks[0][b];
    }
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
    TetBlocks blocks;
    hessian_blocks(s, f, t.inverse.transpose(), t.weight, project_psd, blocks);
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) hess.block<3, 3>(3 * a, 3 * b) = blocks[a][b];
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

}  // namespace hexmesh::untangle

#include "untangle/tet_energy.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Four corner tets at a time, one per lane of a vector of doubles (GCC vector extensions:
// two SSE2 registers on baseline x86-64), with the same operations as the scalar code.
// These vectors never cross a call: every function taking or returning them is
// HEXMESH_LANE_INLINE (below), which is what makes the AVX2 build safe, since an AVX2
// caller would pass them in a register a baseline callee reads from memory. So the ABI
// note about passing them without AVX does not apply (GCC reports it at the end of the
// file: ignored from here on). A new helper on Lanes must be HEXMESH_LANE_INLINE too.
#pragma GCC diagnostic ignored "-Wpsabi"
using Lanes = double __attribute__((vector_size(32)));
using LaneInts = int64_t __attribute__((vector_size(32)));  // comparison results
using LaneBits = uint64_t __attribute__((vector_size(32)));
constexpr int lane_count = 4;

// The lane kernels are inlined into hex_sum, which is built twice: for the baseline and, on
// x86-64, for AVX2 (one 4-double register per vector instead of two SSE2 ones); hex_energy
// and hex_energy_hessian call the second where the CPU has AVX2. The same IEEE operations run
// in the same order (no FMA: contracting a * b + c would round differently; the project
// builds without -march or -mfma), so both give the same bits. Only hex_sum_avx2 is built
// for AVX2: nothing built for it can be linked into a baseline path.
#define HEXMESH_LANE_INLINE __attribute__((always_inline)) inline

HEXMESH_LANE_INLINE Lanes lane_sqrt(Lanes x) {
#if defined(__SSE2__)
    __m128d half[2];
    std::memcpy(half, &x, sizeof x);
    half[0] = _mm_sqrt_pd(half[0]);
    half[1] = _mm_sqrt_pd(half[1]);
    std::memcpy(&x, half, sizeof x);
#else
    for (int l = 0; l < lane_count; ++l) x[l] = std::sqrt(x[l]);
#endif
    return x;
}

HEXMESH_LANE_INLINE bool any_lane(LaneInts mask) {
    for (int l = 0; l < lane_count; ++l)
        if (mask[l]) return true;
    return false;
}

// inverse_cbrt in every lane.
HEXMESH_LANE_INLINE Lanes inverse_cbrt(Lanes x) {
    LaneBits bits;  // unsigned: the shifts are logical, also in NaN lanes
    std::memcpy(&bits, &x, sizeof x);
    bits = 0x553eeeeeeeeef000ULL - ((((bits >> 32) * 0xAAAAAAABULL) >> 33) << 32);
    Lanes y;
    std::memcpy(&y, &bits, sizeof y);
    for (int k = 0; k < 3; ++k) {
        const Lanes r = 1 - x * y * y * y;
        y *= 1 + r * (1.0 / 3 + r * (2.0 / 9));
    }
    const LaneInts normal = (x > 1e-300) & (x < 1e300);
    if (!any_lane(~normal)) return y;
    for (int l = 0; l < lane_count; ++l)
        if (!normal[l]) y[l] = 1 / std::cbrt(x[l]);
    return y;
}

// phi (v0 = 1) in every lane and, from order 1, f_I and f_d, from order 2 f_dd and f_id:
// phi() above.
struct LanePhi {
    Lanes value, f_i, f_d, f_dd, f_id;
};
template <int order>
HEXMESH_LANE_INLINE LanePhi phi_lanes(Lanes i, Lanes d, const EnergyParams& p) {
    const double eps = p.eps, theta = p.theta;
    Lanes x = d, x1 = d * 0 + 1, x2 = d * 0;
    if (eps > 0) {
        Lanes r = lane_sqrt(eps * eps + d * d);
        const LaneInts huge = (d >= 1e100) | (d <= -1e100);
        if (any_lane(huge))
            for (int l = 0; l < lane_count; ++l) r[l] = regularization_radius(d[l], eps);
        const LaneInts positive = d > 0;
        x = positive ? 0.5 * (d + r) : eps * eps / (2 * (r - d));
        if (order >= 1) x1 = x / r;  // 0.5 (1 + d / r), and eps^2 / (2 r (r - d)) for d <= 0
        if (order >= 2) x2 = 0.5 * eps * eps / (r * r * r);
    }
    const Lanes y = inverse_cbrt(x), y2 = y * y, y3 = y2 * y;
    LanePhi f;
    f.value = theta * (0.5 * (y3 + x)) + (1 - theta) / 3 * (i * y2);
    if (order >= 1) {
        const Lanes y5 = y3 * y2;
        const Lanes first = theta * (0.5 * (1 - y3 * y3)) + (1 - theta) * (-2.0 / 9 * i * y5);
        f.f_i = (1 - theta) / 3 * y2;
        f.f_d = first * x1;
        if (order >= 2) {
            f.f_dd = (theta * (y3 * y3 * y3) + (1 - theta) * (10.0 / 27 * i * y5 * y3)) * x1 * x1 +
                     first * x2;
            f.f_id = (1 - theta) * (-2.0 / 9 * y5) * x1;
        }
    }
    return f;
}

// Per corner tet c of a hex, the axis of each of its three edges (its target's diagonal).
constexpr std::array<std::array<int, 3>, 8> corner_axes = [] {
    std::array<std::array<int, 3>, 8> axes{};
    for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 3; ++k)
            axes[c][k] = hex_edge_axis(hex_corner_tets[c][0], hex_corner_tets[c][k + 1]);
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
    TetBlocks blocks;
    hessian_blocks(s, f, t.inverse.transpose(), t.weight, project_psd, blocks);
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) hess.block<3, 3>(3 * a, 3 * b) = blocks[a][b];
    return t.weight * f.value;
}

namespace {

HEXMESH_LANE_INLINE Lanes lane_abs(Lanes x) {
    return x < 0 ? -x : x;
}
HEXMESH_LANE_INLINE Lanes lane_max(Lanes x, Lanes y) {
    return x > y ? x : y;
}

// The largest |a_ij| of a symmetric 3 x 3 matrix (upper triangle) in every lane; NaN where an
// entry is NaN or infinite, so that range tests on it fail there.
HEXMESH_LANE_INLINE Lanes largest_entry(const Lanes (&a)[3][3]) {
    Lanes largest = lane_abs(a[0][0]), sum = a[0][0];
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) largest = lane_max(largest, lane_abs(a[i][j])), sum += a[i][j];
    return largest + 0 * sum;
}

// Scales the symmetric matrix a (upper triangle) by 1 / largest_entry in the lanes where that
// lies in [1e-280, 1e280] (returned: its reciprocal or 1, and `usable`), and replaces it by the
// identity in the others (zero, out of range, not finite), whose results the caller discards.
HEXMESH_LANE_INLINE Lanes normalize_lanes(Lanes (&a)[3][3], LaneInts& usable) {
    const Lanes largest = largest_entry(a);
    usable = (largest >= 1e-280) & (largest <= 1e280);
    const Lanes one = largest * 0 + 1, scale = usable ? 1 / largest : one;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) a[i][j] = usable ? a[i][j] * scale : (i == j ? one : 0 * one);
    return scale;
}

// Cyclic Jacobi rotations on the symmetric 3 x 3 matrix a (upper triangle used) in every
// lane, until every lane's off-diagonal part is below 1e-17 of its largest |a_ii| (at most
// 12 sweeps): a's diagonal becomes its eigenvalues and v (set here) the eigenvectors, as
// columns. No trigonometry, no branch per lane. Its entries must be at most about 1 in
// magnitude (normalize_lanes), so that their squares do not overflow.
HEXMESH_LANE_INLINE void jacobi_lanes(Lanes (&a)[3][3], Lanes (&v)[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i][j] = a[0][0] * 0 + (i == j ? 1 : 0);
    for (int sweep = 0; sweep < 12; ++sweep) {
        const Lanes size =
            lane_max(lane_max(lane_abs(a[0][0]), lane_abs(a[1][1])), lane_abs(a[2][2]));
        const Lanes off = lane_abs(a[0][1]) + lane_abs(a[0][2]) + lane_abs(a[1][2]);
        if (!any_lane(off > 1e-17 * size)) break;
        for (const auto& [p, q] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
            const int r = 3 - p - q;
            const Lanes apq = a[p][q], d = a[q][q] - a[p][p];
            // t = tan of the angle that zeroes a_pq: 2 a_pq sgn(d) / (|d| + sqrt(d^2 + 4 a_pq^2)).
            const Lanes denominator = lane_abs(d) + lane_sqrt(d * d + 4 * apq * apq);
            const Lanes t =
                denominator > 0 ? 2 * apq / (d < 0 ? -denominator : denominator) : d * 0;
            const Lanes c = 1 / lane_sqrt(1 + t * t), sn = t * c;
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            a[p][q] = d * 0;
            Lanes& arp = p < r ? a[p][r] : a[r][p];
            Lanes& arq = q < r ? a[q][r] : a[r][q];
            const Lanes rp = arp, rq = arq;
            arp = c * rp - sn * rq;
            arq = sn * rp + c * rq;
            for (int k = 0; k < 3; ++k) {
                const Lanes vp = v[k][p], vq = v[k][q];
                v[k][p] = c * vp - sn * vq;
                v[k][q] = sn * vp + c * vq;
            }
        }
    }
}

// signed_svd in every lane, the eigensystem of S^T S by jacobi_lanes: V its eigenvectors
// sorted by decreasing eigenvalue and turned into a rotation; U by Gram-Schmidt on S V as in
// signed_svd; sigma the diagonal of U^T S V. s[3 k + c] = S(c, k). Lanes whose S^T S is zero,
// not finite or out of range (largest entry outside [1e-280, 1e280]) take the scalar
// signed_svd.
HEXMESH_LANE_INLINE void signed_svd_lanes(const Lanes (&s)[9], Lanes (&u)[3][3], Lanes (&sigma)[3],
                                          Lanes (&v)[3][3]) {
    // A = S^T S, scaled by its largest entry (the eigenvectors do not change).
    Lanes a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            a[i][j] =
                s[3 * i] * s[3 * j] + s[3 * i + 1] * s[3 * j + 1] + s[3 * i + 2] * s[3 * j + 2];
    LaneInts usable;
    normalize_lanes(a, usable);
    jacobi_lanes(a, v);
    // Eigenvalues largest first: compare-and-swap (0, 1), (0, 2), (1, 2), columns of V with them.
    Lanes lambda[3] = {a[0][0], a[1][1], a[2][2]};
    for (const auto& [i, j] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
        const LaneInts swap = lambda[i] < lambda[j];
        const Lanes li = lambda[i];
        lambda[i] = swap ? lambda[j] : li;
        lambda[j] = swap ? li : lambda[j];
        for (int k = 0; k < 3; ++k) {
            const Lanes vi = v[k][i];
            v[k][i] = swap ? v[k][j] : vi;
            v[k][j] = swap ? vi : v[k][j];
        }
    }
    const Lanes det_v = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                        v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                        v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
    for (int k = 0; k < 3; ++k) v[k][2] = det_v < 0 ? -v[k][2] : v[k][2];
    // S V, then U: u0 = unit(sv0), u1 = unit(sv1 - (u0 . sv1) u0), u2 = u0 x u1.
    Lanes sv[3][3];  // sv[k][r] = (S V)(r, k)
    for (int k = 0; k < 3; ++k)
        for (int r = 0; r < 3; ++r)
            sv[k][r] = s[r] * v[0][k] + s[3 + r] * v[1][k] + s[6 + r] * v[2][k];
    const Lanes zero{}, one = zero + 1;
    const Lanes n0 = lane_sqrt(sv[0][0] * sv[0][0] + sv[0][1] * sv[0][1] + sv[0][2] * sv[0][2]);
    const LaneInts has0 = n0 > 1e-300;
    Lanes u0[3];
    for (int r = 0; r < 3; ++r) u0[r] = has0 ? sv[0][r] / n0 : (r == 0 ? one : zero);
    // A unit vector orthogonal to u0 (like Eigen's unitOrthogonal: in the xy-plane unless u0 is
    // nearly along z).
    const LaneInts along_z = (u0[0] * u0[0] + u0[1] * u0[1]) <= 1e-24 * (u0[2] * u0[2]);
    const Lanes nxy = lane_sqrt(u0[0] * u0[0] + u0[1] * u0[1]),
                nyz = lane_sqrt(u0[1] * u0[1] + u0[2] * u0[2]);
    const Lanes normal[3] = {along_z ? zero : -u0[1] / nxy, along_z ? -u0[2] / nyz : u0[0] / nxy,
                             along_z ? u0[1] / nyz : zero};
    const Lanes dot01 = u0[0] * sv[1][0] + u0[1] * sv[1][1] + u0[2] * sv[1][2];
    Lanes w1[3];
    for (int r = 0; r < 3; ++r) w1[r] = sv[1][r] - dot01 * u0[r];
    const Lanes n1 = lane_sqrt(w1[0] * w1[0] + w1[1] * w1[1] + w1[2] * w1[2]);
    const LaneInts has1 = n1 > 1e-300;
    Lanes u1[3];
    for (int r = 0; r < 3; ++r) u1[r] = has1 ? w1[r] / n1 : normal[r];
    const Lanes u2[3] = {u0[1] * u1[2] - u0[2] * u1[1], u0[2] * u1[0] - u0[0] * u1[2],
                         u0[0] * u1[1] - u0[1] * u1[0]};
    for (int r = 0; r < 3; ++r) u[r][0] = u0[r], u[r][1] = u1[r], u[r][2] = u2[r];
    for (int k = 0; k < 3; ++k)
        sigma[k] = u[0][k] * sv[k][0] + u[1][k] * sv[k][1] + u[2][k] * sv[k][2];
    if (!any_lane(~usable)) return;
    for (int l = 0; l < lane_count; ++l) {
        if (usable[l]) continue;
        Mat3 sl, ul, vl;
        Vec3 sigma_l;
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) sl(c, k) = s[3 * k + c][l];
        signed_svd(sl, ul, sigma_l, vl);
        for (int r = 0; r < 3; ++r) {
            sigma[r][l] = sigma_l[r];
            for (int c = 0; c < 3; ++c) u[r][c][l] = ul(r, c), v[r][c][l] = vl(r, c);
        }
    }
}

// The PSD Hessian blocks of the corners of group g (hessian_blocks with g = diag(scale)),
// added to hess.
HEXMESH_LANE_INLINE void corner_hessian_lanes(int g, const Lanes (&s)[9], const Lanes (&scale)[3],
                                              const LanePhi& f, double weight, HexHessian& hess) {
    // Signed SVD S = U diag(sigma) V^T.
    Lanes u[3][3], v[3][3], sigma[3];
    signed_svd_lanes(s, u, sigma, v);
    // The scalings' 3 x 3 matrix `a`, weighted, clamped where it is not positive definite.
    const Lanes d_i[3] = {sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]};
    Lanes a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a[i][j] = 2 * f.f_id * (sigma[i] * d_i[j] + sigma[j] * d_i[i]) +
                      f.f_dd * d_i[i] * d_i[j] + (i == j ? 2 * f.f_i : f.f_d * sigma[3 - i - j]);
    const Lanes minor = a[0][0] * a[1][1] - a[0][1] * a[0][1];
    const Lanes det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                      a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                      a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    const LaneInts definite = (a[0][0] > 0) & (minor > 0) & (det > 0);
    Lanes scaling[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) scaling[i][j] = weight * a[i][j];
    if (any_lane(~definite)) {
        // weight a+ = V diag(weight max(lambda, 0)) V^T, a scaled to about 1 for the rotations.
        Lanes e[3][3], w[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j) e[i][j] = a[i][j];
        LaneInts usable;
        const Lanes scale = normalize_lanes(e, usable);
        jacobi_lanes(e, w);
        Lanes kept[3];
        for (int k = 0; k < 3; ++k)
            kept[k] = e[k][k] > 0 ? weight * (e[k][k] / scale) : 0 * e[k][k];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const Lanes clamped = w[i][0] * kept[0] * w[j][0] + w[i][1] * kept[1] * w[j][1] +
                                      w[i][2] * kept[2] * w[j][2];
                scaling[i][j] = definite ? scaling[i][j] : clamped;
            }
        for (int l = 0; l < lane_count; ++l) {  // a zero or out-of-range a: Eigen's closed form
            if (definite[l] || usable[l]) continue;
            Mat3 al;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) al(i, j) = a[i][j][l];
            Eigen::SelfAdjointEigenSolver<Mat3> eigen;
            eigen.computeDirect(al);
            const Mat3 clamped = eigen.eigenvectors() *
                                 (weight * eigen.eigenvalues().cwiseMax(0.0)).asDiagonal() *
                                 eigen.eigenvectors().transpose();
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) scaling[i][j][l] = clamped(i, j);
        }
    }
    // Twists and flips: pair[k] = weight (flip + twist) / 2, twist_flip[k] = weight (flip -
    // twist) / 2, both clamped, for the pair (i, j) whose third index is k.
    Lanes pair[3], twist_flip[3];
    for (int k = 0; k < 3; ++k) {
        Lanes twist = 2 * f.f_i + f.f_d * sigma[k], flip = 2 * f.f_i - f.f_d * sigma[k];
        twist = twist > 0 ? twist : 0 * twist;
        flip = flip > 0 ? flip : 0 * flip;
        pair[k] = 0.5 * weight * (flip + twist);
        twist_flip[k] = 0.5 * weight * (flip - twist);
    }
    // x_a = V^T g_a with g_a = scale_a e_a: x[j][a] = V(a, j) scale_a.
    Lanes x[3][3];
    for (int j = 0; j < 3; ++j)
        for (int a1 = 0; a1 < 3; ++a1) x[j][a1] = v[a1][j] * scale[a1];
    // Blocks (a, b), a, b >= 1: U K_ab U^T; vertex 0: minus sums.
    Lanes block[4][4][3][3];
    for (int a1 = 0; a1 < 3; ++a1)
        for (int b1 = a1; b1 < 3; ++b1) {
            Lanes k[3][3];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    k[i][j] = scaling[i][j] * x[i][a1] * x[j][b1];
                    if (i != j) k[i][j] += twist_flip[3 - i - j] * x[i][b1] * x[j][a1];
                }
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    if (j != i) k[i][i] += pair[3 - i - j] * x[j][a1] * x[j][b1];
            Lanes uk[3][3];
            for (int r = 0; r < 3; ++r)
                for (int j = 0; j < 3; ++j)
                    uk[r][j] = u[r][0] * k[0][j] + u[r][1] * k[1][j] + u[r][2] * k[2][j];
            auto& out = block[a1 + 1][b1 + 1];
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    out[r][c] = uk[r][0] * u[c][0] + uk[r][1] * u[c][1] + uk[r][2] * u[c][2];
            if (b1 != a1)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) block[b1 + 1][a1 + 1][c][r] = out[r][c];
        }
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            block[0][0][r][c] = 0 * block[1][1][r][c];
            for (int b = 1; b < 4; ++b) {
                block[0][b][r][c] = -(block[1][b][r][c] + block[2][b][r][c] + block[3][b][r][c]);
                block[0][0][r][c] -= block[0][b][r][c];
            }
        }
    for (int b = 1; b < 4; ++b)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) block[b][0][c][r] = block[0][b][r][c];
    for (int l = 0; l < lane_count; ++l) {
        const auto& t = hex_corner_tets[4 * g + l];
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                if (t[i] > t[j]) continue;
                Mat3& target = hess.block[t[i]][t[j]];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) target(r, c) += block[i][j][r][c][l];
            }
    }
}

// hex_energy (order 0), with its gradient (1) and with its PSD Hessian too (2; hessian_blocks
// above, the SVD per lane), for the corners 4 g .. 4 g + 3 in the lanes. The gradient and
// the Hessian blocks are added to grad and hess.
template <int order>
HEXMESH_LANE_INLINE bool hex_corner_lanes(int g, const Mat38& y, const Vec3& inverse, double weight,
                                          const EnergyParams& p, double& total, Mat38* grad,
                                          HexHessian* hess) {
    // s[3 k + c]: component c of column k of S (edge k of the corner, scaled).
    Lanes s[9], scale[3];
    for (int l = 0; l < lane_count; ++l) {
        const int corner = 4 * g + l;
        const auto& t = hex_corner_tets[corner];
        for (int k = 0; k < 3; ++k) {
            scale[k][l] = inverse[corner_axes[corner][k]];
            for (int c = 0; c < 3; ++c)
                s[3 * k + c][l] = (y(c, t[k + 1]) - y(c, t[0])) * scale[k][l];
        }
    }
    // Cofactor columns: s1 x s2, s2 x s0, s0 x s1.
    Lanes cof[9];
    for (int k = 0; k < 3; ++k) {
        const Lanes* a = s + 3 * ((k + 1) % 3);
        const Lanes* b = s + 3 * ((k + 2) % 3);
        cof[3 * k + 0] = a[1] * b[2] - a[2] * b[1];
        cof[3 * k + 1] = a[2] * b[0] - a[0] * b[2];
        cof[3 * k + 2] = a[0] * b[1] - a[1] * b[0];
    }
    const Lanes d = s[0] * cof[0] + s[1] * cof[1] + s[2] * cof[2];
    if (p.eps <= 0 && any_lane(d <= 0)) return false;
    Lanes i = s[0] * s[0];
    for (int m = 1; m < 9; ++m) i += s[m] * s[m];
    const LanePhi f = phi_lanes<order>(i, d, p);
    const Lanes f_i = f.f_i, f_d = f.f_d;
    for (int l = 0; l < lane_count; ++l) total += f.value[l];
    if (order == 0) return true;
    // d phi / d S = 2 f_I S + f_d cof S, scaled back per column.
    Lanes dq[9];
    for (int k = 0; k < 3; ++k) {
        const Lanes w = weight * scale[k];
        for (int c = 0; c < 3; ++c)
            dq[3 * k + c] = w * (2 * f_i * s[3 * k + c] + f_d * cof[3 * k + c]);
    }
    for (int l = 0; l < lane_count; ++l) {
        const auto& t = hex_corner_tets[4 * g + l];
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (int k = 0; k < 3; ++k) {
                (*grad)(c, t[k + 1]) += dq[3 * k + c][l];
                sum += dq[3 * k + c][l];
            }
            (*grad)(c, t[0]) -= sum;
        }
    }
    if (order == 2) corner_hessian_lanes(g, s, scale, f, weight, *hess);
    return true;
}

}  // namespace

namespace {

// Corner tet c has S = [y_a - y_c, y_b - y_c, y_d - y_c] diag(1 / edges along its axes):
// scaled edge vectors, no matrix product; its gradient is d phi / d S scaled back. The
// corners run four at a time, one per vector lane: the energy (order 0), with the gradient
// (1), with the gradient and the PSD Hessian (2).
template <int order>
HEXMESH_LANE_INLINE double hex_sum(const Mat38& y, const Vec3& edges, const EnergyParams& p,
                                   Mat38* grad, HexHessian* hess) {
    const Vec3 inverse = edges.cwiseInverse();
    const double weight = edges.prod() / 6;
    if (order >= 1) grad->setZero();
    if (order == 2)
        for (const auto& [a, b] : hex_hessian_pairs) hess->block[a][b].setZero();
    double total = 0;
    for (int g = 0; g < 2; ++g)
        if (!hex_corner_lanes<order>(g, y, inverse, weight, p, total, grad, hess)) return infinity;
    return weight * total;
}

#if defined(__x86_64__) && defined(__GNUC__)
template <int order>
__attribute__((target("avx2"))) double hex_sum_avx2(const Mat38& y, const Vec3& edges,
                                                    const EnergyParams& p, Mat38* grad,
                                                    HexHessian* hess) {
    return hex_sum<order>(y, edges, p, grad, hess);
}

bool cpu_has_avx2() {
    __builtin_cpu_init();  // this runs among the static initializers
    return __builtin_cpu_supports("avx2");
}
const bool use_avx2 = cpu_has_avx2();

template <int order>
double hex_sum_best(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad,
                    HexHessian* hess) {
    return use_avx2 ? hex_sum_avx2<order>(y, edges, p, grad, hess)
                    : hex_sum<order>(y, edges, p, grad, hess);
}
#else
template <int order>
double hex_sum_best(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad,
                    HexHessian* hess) {
    return hex_sum<order>(y, edges, p, grad, hess);
}
#endif

}  // namespace

double hex_energy(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad) {
    return grad ? hex_sum_best<1>(y, edges, p, grad, nullptr)
                : hex_sum_best<0>(y, edges, p, nullptr, nullptr);
}

double hex_energy_hessian(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38& grad,
                          HexHessian& hess) {
    return hex_sum_best<2>(y, edges, p, &grad, &hess);
}

double hex_energy_baseline(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad,
                           HexHessian* hess) {
    if (hess) return hex_sum<2>(y, edges, p, grad, hess);
    return grad ? hex_sum<1>(y, edges, p, grad, nullptr)
                : hex_sum<0>(y, edges, p, nullptr, nullptr);
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

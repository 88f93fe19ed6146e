// hex_energy and hex_energy_hessian: the 8 corner tets of a hex four at a time, one per
// vector lane, built for baseline x86-64 and for AVX2, and the choice between the two builds
// at run time.
#include <Eigen/Eigenvalues>
#include <array>
#include <limits>

#include "hexmesh/core/reference_hex.h"
#include "untangle/lanes.h"
#include "untangle/regularization.h"
#include "untangle/svd_lanes.h"
#include "untangle/tet_energy.h"

namespace hexmesh::untangle {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// phi (v0 = 1) in every lane and, from order 1, f_I and f_d, from order 2 f_dd and f_id:
// phi() of untangle/tet_energy.cpp.
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

// The scalings' 3 x 3 matrix `a` of hessian_blocks in every lane, times weight, clamped
// (weight a+) where it is not positive definite.
HEXMESH_LANE_INLINE void scaling_lanes(const Lanes (&sigma)[3], const LanePhi& f, double weight,
                                       Lanes (&scaling)[3][3]) {
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
}

// Adds the 4 x 4 blocks of the corners of group g, one corner per lane, to hess: block (i, j)
// of a corner where its node i is at most its node j.
HEXMESH_LANE_INLINE void add_corner_blocks(int g, const Lanes (&block)[4][4][3][3],
                                           HexHessian& hess) {
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

// The PSD Hessian blocks of the corners of group g (hessian_blocks of untangle/tet_energy.cpp
// with g = diag(scale)), added to hess.
HEXMESH_LANE_INLINE void corner_hessian_lanes(int g, const Lanes (&s)[9], const Lanes (&scale)[3],
                                              const LanePhi& f, double weight, HexHessian& hess) {
    // Signed SVD S = U diag(sigma) V^T.
    Lanes u[3][3], v[3][3], sigma[3];
    signed_svd_lanes(s, u, sigma, v);
    // The scalings' matrix, weighted and clamped.
    Lanes scaling[3][3];
    scaling_lanes(sigma, f, weight, scaling);
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
    add_corner_blocks(g, block, hess);
}

// hex_energy (order 0), with its gradient (1) and with its PSD Hessian too (2; hessian_blocks
// of untangle/tet_energy.cpp, the SVD per lane), for the corners 4 g .. 4 g + 3 in the
// lanes. The gradient and the Hessian blocks are added to grad and hess.
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

}  // namespace hexmesh::untangle

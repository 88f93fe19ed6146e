#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>

#include "hexmesh/core/reference_hex.h"
#include "untangle/problem.h"
#include "untangle/tet_energy.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

namespace {

Mat34 regular_tet(double edge) {
    const Mat3 h = regular_tet_target(edge).inverse.inverse();
    Mat34 y;
    y.col(0) = Vec3::Zero();
    y.rightCols<3>() = h;
    return y;
}

Mat34 random_tet(std::mt19937& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    Mat34 y = regular_tet(1.0);
    for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 3; ++c) y(c, a) += u(rng);
    return y;
}

// Central-difference gradient of tet_energy.
Mat34 fd_gradient(const Mat34& y, const TetTarget& t, const EnergyParams& p, double h) {
    Mat34 g;
    for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 3; ++c) {
            Mat34 yp = y, ym = y;
            yp(c, a) += h;
            ym(c, a) -= h;
            g(c, a) = (tet_energy(yp, t, p) - tet_energy(ym, t, p)) / (2 * h);
        }
    return g;
}

}  // namespace

TEST(TetEnergy, MinimumIsExactlyAtTheTarget) {
    for (const TetTarget& t : {regular_tet_target(2.0), box_corner_target(Vec3(1, 2, 0.5))}) {
        const Mat3 h = t.inverse.inverse();
        Mat34 y;
        y.col(0) = Vec3(1, -2, 3);
        for (int a = 1; a < 4; ++a) y.col(a) = y.col(0) + h.col(a - 1);
        Mat34 g;
        const double e = tet_energy_gradient(y, t, {0.8, 0}, g);
        EXPECT_NEAR(e, t.weight, 1e-14);  // phi = 1 at the target
        EXPECT_LT(g.norm(), 1e-12);
        // Any perturbation raises the energy.
        std::mt19937 rng(3);
        for (int k = 0; k < 50; ++k) {
            Mat34 z = y + 1e-3 * Mat34::Random();
            EXPECT_GT(tet_energy(z, t, {0.8, 0}), e);
        }
    }
}

TEST(TetEnergy, InvariantUnderRotationAndTranslation) {
    std::mt19937 rng(7);
    const TetTarget t = regular_tet_target(1.0);
    for (int k = 0; k < 20; ++k) {
        const Mat34 y = random_tet(rng, 0.3);
        const Mat3 r = Eigen::AngleAxisd(0.3 + k, Vec3(1, 2, 3).normalized()).toRotationMatrix();
        Mat34 z = r * y;
        z.colwise() += Vec3(5, -1, 2);
        for (double eps : {0.0, 0.1}) {
            if (tet_det(y, t) > 0 || eps > 0) {
                EXPECT_NEAR(tet_energy(z, t, {0.8, eps}), tet_energy(y, t, {0.8, eps}), 1e-12);
            }
        }
    }
}

TEST(TetEnergy, GradientMatchesFiniteDifferences) {
    std::mt19937 rng(11);
    const TetTarget t = box_corner_target(Vec3(1.0, 0.5, 2.0));
    for (int k = 0; k < 200; ++k) {
        const Mat34 y = random_tet(rng, 0.6);  // some of them inverted
        for (double eps : {0.0, 0.05, 1.0}) {
            const EnergyParams p{0.8, eps};
            Mat34 g;
            const double e = tet_energy_gradient(y, t, p, g);
            if (!std::isfinite(e)) {
                EXPECT_LE(tet_det(y, t), 0.0);
                continue;
            }
            const Mat34 fd = fd_gradient(y, t, p, 1e-6);
            EXPECT_LT((g - fd).norm(), 1e-5 * (1 + g.norm())) << "case " << k << " eps " << eps;
        }
    }
}

TEST(TetEnergy, ExactHessianMatchesFiniteDifferences) {
    std::mt19937 rng(5);
    const TetTarget t = box_corner_target(Vec3(1.0, 0.7, 1.3));
    int checked = 0;
    for (int k = 0; k < 100; ++k) {
        const Mat34 y = random_tet(rng, 0.5);  // some tangled: checked with eps > 0
        for (double eps : {0.0, 0.01, 0.5}) {
            const EnergyParams p{0.8, eps};
            Mat34 g;
            Mat12 h;
            if (!std::isfinite(tet_energy_hessian(y, t, p, g, h, false))) continue;
            Mat12 fd;
            const double step = 1e-6;
            for (int a = 0; a < 4; ++a)
                for (int c = 0; c < 3; ++c) {
                    Mat34 yp = y, ym = y, gp, gm;
                    yp(c, a) += step;
                    ym(c, a) -= step;
                    tet_energy_gradient(yp, t, p, gp);
                    tet_energy_gradient(ym, t, p, gm);
                    const Mat34 col = (gp - gm) / (2 * step);
                    for (int b = 0; b < 4; ++b) fd.block<3, 1>(3 * b, 3 * a + c) = col.col(b);
                }
            EXPECT_LT((h - fd).norm(), 1e-5 * (1 + h.norm())) << "case " << k << " eps " << eps;
            ++checked;
        }
    }
    EXPECT_GT(checked, 200);
}

TEST(TetEnergy, ProjectionKeepsAPositiveDefiniteHessian) {
    // At a stretched but untangled element where the exact Hessian is PSD, clamping is a no-op.
    const TetTarget t = regular_tet_target(1.0);
    Mat34 y = regular_tet(1.0);
    y.col(3) += Vec3(0, 0, 0.05);
    Mat34 g;
    Mat12 exact, projected;
    tet_energy_hessian(y, t, {0.8, 0}, g, exact, false);
    tet_energy_hessian(y, t, {0.8, 0}, g, projected, true);
    Eigen::SelfAdjointEigenSolver<Mat12> eig(exact);
    if (eig.eigenvalues().minCoeff() >= -1e-12 * exact.norm()) {
        EXPECT_LT((exact - projected).norm(), 1e-9 * exact.norm());
    }
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat12>(projected).eigenvalues().minCoeff(),
              -1e-12 * exact.norm());
}

TEST(TetEnergy, ProjectedHessianIsPositiveSemiDefiniteEvenWhenTangled) {
    std::mt19937 rng(13);
    const TetTarget t = regular_tet_target(1.0);
    for (int k = 0; k < 200; ++k) {
        const Mat34 y = random_tet(rng, 0.8);
        Mat34 g;
        Mat12 h;
        tet_energy_hessian(y, t, {0.8, 0.1}, g, h);
        Eigen::SelfAdjointEigenSolver<Mat12> eig(h);
        EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-9 * (1 + h.norm()));
        EXPECT_LT((h - h.transpose()).norm(), 1e-10 * (1 + h.norm()));
    }
}

TEST(TetEnergy, BarrierIsInfiniteOnInvertedElementsAndFiniteWithEps) {
    Mat34 y = regular_tet(1.0);
    y.col(3) *= -1;  // through the opposite face
    const TetTarget t = regular_tet_target(1.0);
    EXPECT_LT(tet_det(y, t), 0);
    EXPECT_TRUE(std::isinf(tet_energy(y, t, {0.8, 0})));
    EXPECT_TRUE(std::isfinite(tet_energy(y, t, {0.8, 1e-3})));
}

TEST(TetEnergy, HexEnergyIsTheSumOverItsCornerTets) {
    // A box of edges (1.0, 0.5, 2.0) with its nodes displaced, some corners inverted.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    const Vec3 edges(1.0, 0.5, 2.0);
    const std::array<Vec3, 8> unit = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                      Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
    int finite = 0, infinite = 0;
    for (int k = 0; k < 100; ++k) {
        Mat38 y;
        for (int a = 0; a < 8; ++a)
            y.col(a) = unit[a].cwiseProduct(edges) + Vec3(u(rng), u(rng), u(rng));
        for (double eps : {0.0, 0.05}) {
            const EnergyParams p{0.8, eps};
            double sum = 0;
            Mat38 sum_grad = Mat38::Zero();
            for (int c = 0; c < 8; ++c) {
                const auto& t = hex_corner_tets[c];
                Mat34 yc, gc;
                for (int a = 0; a < 4; ++a) yc.col(a) = y.col(t[a]);
                sum += tet_energy_gradient(yc, hex_corner_target(c, edges), p, gc);
                if (std::isfinite(sum))
                    for (int a = 0; a < 4; ++a) sum_grad.col(t[a]) += gc.col(a);
            }
            Mat38 grad;
            const double e = hex_energy(y, edges, p, &grad);
            EXPECT_EQ(hex_energy(y, edges, p), e);
            if (!std::isfinite(sum)) {
                EXPECT_FALSE(std::isfinite(e)) << "case " << k;
                ++infinite;
                continue;
            }
            ++finite;
            EXPECT_NEAR(e, sum, 1e-12 * std::abs(sum)) << "case " << k << " eps " << eps;
            EXPECT_LT((grad - sum_grad).norm(), 1e-12 * (1 + sum_grad.norm()))
                << "case " << k << " eps " << eps;
        }
    }
    EXPECT_GT(finite, 50);
    EXPECT_GT(infinite, 0);  // the barrier case was met
}

namespace {

// A box of edges `edges` with its nodes displaced by up to `spread` (some corners inverted).
Mat38 displaced_box(std::mt19937& rng, const Vec3& edges, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    const std::array<Vec3, 8> unit = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                      Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
    Mat38 y;
    for (int a = 0; a < 8; ++a)
        y.col(a) = unit[a].cwiseProduct(edges) + Vec3(u(rng), u(rng), u(rng));
    return y;
}

// The corner tets' energies, gradients and Hessians (the scalar code) summed over a hex: what
// the hex kernels must give. Energy +inf (the rest partial) where a corner's is.
struct CornerSums {
    double energy = 0;
    Mat38 grad = Mat38::Zero();
    Eigen::Matrix<double, 24, 24> hess = Eigen::Matrix<double, 24, 24>::Zero();  // 8 x 8 blocks
};
CornerSums sum_over_corner_tets(const Mat38& y, const Vec3& edges, const EnergyParams& p) {
    CornerSums sums;
    for (int c = 0; c < 8; ++c) {
        const auto& t = hex_corner_tets[c];
        Mat34 yc, gc;
        Mat12 hc;
        for (int a = 0; a < 4; ++a) yc.col(a) = y.col(t[a]);
        sums.energy += tet_energy_hessian(yc, hex_corner_target(c, edges), p, gc, hc);
        if (!std::isfinite(sums.energy)) break;
        for (int a = 0; a < 4; ++a) {
            sums.grad.col(t[a]) += gc.col(a);
            for (int b = 0; b < 4; ++b)
                sums.hess.block<3, 3>(3 * t[a], 3 * t[b]) += hc.block<3, 3>(3 * a, 3 * b);
        }
    }
    return sums;
}

}  // namespace

TEST(TetEnergy, HexHessianIsTheSumOverItsCornerTets) {
    std::mt19937 rng(11);
    const Vec3 edges(1.0, 0.5, 2.0);
    int checked = 0;
    for (int k = 0; k < 100; ++k) {
        const Mat38 y = displaced_box(rng, edges, 0.3);
        for (double eps : {0.0, 0.05}) {
            const EnergyParams p{0.8, eps};
            Mat38 grad;
            HexHessian hess;
            const double e = hex_energy_hessian(y, edges, p, grad, hess);
            EXPECT_EQ(bool(std::isfinite(e)), bool(std::isfinite(hex_energy(y, edges, p))))
                << "case " << k;
            if (!std::isfinite(e)) continue;
            const CornerSums corners = sum_over_corner_tets(y, edges, p);
            const double sum_e = corners.energy;
            const Mat38& sum_grad = corners.grad;
            const auto& sum = corners.hess;
            EXPECT_NEAR(e, sum_e, 1e-12 * std::abs(sum_e));
            EXPECT_LT((grad - sum_grad).norm(), 1e-12 * (1 + sum_grad.norm()));
            for (const auto& [a, b] : hex_hessian_pairs) {
                const Mat3 want = sum.block<3, 3>(3 * a, 3 * b);
                EXPECT_LT((hess.block[a][b] - want).norm(), 1e-12 * (1 + sum.norm()));
            }
            // The pairs not listed (the body diagonals, e.g. nodes 0 and 6) are not coupled.
            const Mat3 body_diagonal = sum.block<3, 3>(0, 18);
            EXPECT_EQ(body_diagonal.norm(), 0.0);
            ++checked;
        }
    }
    EXPECT_GT(checked, 100);
}

// Where the CPU has AVX2, hex_energy runs a build of the lane kernels for it; it must give the
// baseline build's bits (energy, gradient, Hessian): the AVX2 path changes no result.
TEST(TetEnergy, HexEnergyGivesTheBaselineBuildsBits) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: one build only";
#endif
    std::mt19937 rng(17);
    const Vec3 edges(0.7, 1.3, 0.4);
    for (int k = 0; k < 200; ++k) {
        const Mat38 y = displaced_box(rng, edges, 0.25);
        for (double eps : {0.0, 0.03}) {
            const EnergyParams p{0.7, eps};
            Mat38 g, g_base, gh, gh_base;
            HexHessian h, h_base;
            const double e = hex_energy(y, edges, p, &g);
            const double e_base = hex_energy_baseline(y, edges, p, &g_base);
            EXPECT_EQ(hex_energy(y, edges, p), hex_energy_baseline(y, edges, p, nullptr)) << k;
            ASSERT_EQ(e, e_base) << k;
            if (!std::isfinite(e)) continue;
            EXPECT_EQ(g, g_base) << k;
            EXPECT_EQ(hex_energy_hessian(y, edges, p, gh, h),
                      hex_energy_baseline(y, edges, p, &gh_base, &h_base));
            EXPECT_EQ(gh, gh_base) << k;
            for (const auto& [a, b] : hex_hessian_pairs)
                EXPECT_EQ(h.block[a][b], h_base.block[a][b]) << k;
        }
    }
}

namespace {

// Hexes where the Hessian lanes' eigensolver meets its special cases: repeated singular values
// (an undistorted box), rank-deficient corners (a collapsed edge, a flattened hex), inverted
// corners (a mirrored box), a heavily tangled one, and scales at which S^T S is near the
// limits of the rotations' range or beyond it (the scalar fallback). Not smaller than 1e-20
// in range: at eps 0 the barrier's second derivative (det^(-8/3)) overflows there, in the
// scalar code too.
std::vector<std::pair<std::string, Mat38>> special_hexes(const Vec3& edges) {
    std::mt19937 rng(5);
    const Mat38 box = displaced_box(rng, edges, 0.0);
    std::vector<std::pair<std::string, Mat38>> hexes = {{"box", box}};
    Mat38 y = box;
    y.col(6) = y.col(5);
    hexes.push_back({"collapsed edge", y});
    y = box;
    y.row(2).setZero();
    hexes.push_back({"flat", y});
    y = box;
    y.row(0) *= -1;
    hexes.push_back({"mirrored", y});
    hexes.push_back({"tangled", displaced_box(rng, edges, 1.0)});
    const Mat38 distorted = displaced_box(rng, edges, 0.2);
    for (double scale : {1e-20, 1e100, 1e-145, 1e145})
        hexes.push_back({(std::ostringstream() << "scaled " << scale).str(), scale * distorted});
    return hexes;
}

}  // namespace

TEST(TetEnergy, HexHessianOfDegenerateAndScaledHexesIsTheSumOverItsCornerTets) {
    const Vec3 edges(0.7, 1.3, 0.4);
    for (const auto& [name, y] : special_hexes(edges))
        for (double eps : {0.0, 0.05}) {
            const EnergyParams p{0.8, eps};
            Mat38 grad;
            HexHessian hess;
            const double e = hex_energy_hessian(y, edges, p, grad, hess);
            const CornerSums corners = sum_over_corner_tets(y, edges, p);
            const double sum_e = corners.energy;
            const auto& sum = corners.hess;
            ASSERT_EQ(bool(std::isfinite(e)), bool(std::isfinite(sum_e)))
                << name << ", eps " << eps;
            if (!std::isfinite(e)) continue;
            EXPECT_NEAR(e, sum_e, 1e-12 * std::abs(sum_e)) << name << ", eps " << eps;
            for (const auto& [a, b] : hex_hessian_pairs) {
                const Mat3& got = hess.block[a][b];
                EXPECT_TRUE(got.allFinite()) << name << ", eps " << eps;
                EXPECT_LE((got - sum.block<3, 3>(3 * a, 3 * b)).norm(), 1e-10 * sum.norm())
                    << name << ", eps " << eps << ", block " << a << " " << b;
            }
#if defined(__x86_64__) && defined(__GNUC__)
            if (!__builtin_cpu_supports("avx2")) continue;
#endif
            Mat38 g_base, gh;
            HexHessian h_base;
            EXPECT_EQ(e, hex_energy_baseline(y, edges, p, &g_base, &h_base)) << name;
            for (const auto& [a, b] : hex_hessian_pairs)
                EXPECT_EQ(hess.block[a][b], h_base.block[a][b]) << name;
        }
}

TEST(TetEnergy, HexEnergyIsNotFiniteWithANanOrInfiniteNode) {
    std::mt19937 rng(3);
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity()})
        for (int node = 0; node < 8; ++node)
            for (double eps : {0.0, 0.05}) {
                Mat38 y = displaced_box(rng, Vec3::Ones(), 0.1);
                y(node % 3, node) = bad;
                Mat38 grad;
                const EnergyParams p{0.8, eps};
                EXPECT_FALSE(std::isfinite(hex_energy(y, Vec3::Ones(), p)));
                EXPECT_FALSE(std::isfinite(hex_energy(y, Vec3::Ones(), p, &grad)));
            }
}

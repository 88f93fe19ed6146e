#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "untangle/triangle_energy.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

namespace {

// A right-angle triangle in the plane z = 3 with legs a (along x) and b (along y), seen
// counter-clockwise from +z.
Mat3 corner_triangle(double a, double b) {
    Mat3 y;
    y.col(0) = Vec3(1, -2, 3);
    y.col(1) = y.col(0) + Vec3(a, 0, 0);
    y.col(2) = y.col(0) + Vec3(0, b, 0);
    return y;
}

Mat3 random_triangle(std::mt19937& rng, double spread) {
    std::uniform_real_distribution<double> u(-spread, spread);
    Mat3 y = corner_triangle(1, 1);
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) y(c, a) += u(rng);
    return y;
}

const Vec3 up(0, 0, 1);
const TriangleTarget target = rectangle_corner_target(1.5, 0.5);

Mat3 fd_gradient(const Mat3& y, const Vec3& n, const TriangleTarget& t, const EnergyParams& p,
                 double h) {
    Mat3 g;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
            Mat3 yp = y, ym = y;
            yp(c, a) += h;
            ym(c, a) -= h;
            g(c, a) = (triangle_energy(yp, n, t, p) - triangle_energy(ym, n, t, p)) / (2 * h);
        }
    return g;
}

}  // namespace

TEST(TriangleEnergy, MinimumIsExactlyAtTheTarget) {
    const Mat3 y = corner_triangle(1.5, 0.5);
    Mat3 g;
    const double e = triangle_energy_gradient(y, up, target, {0.8, 0}, g);
    EXPECT_NEAR(e, target.weight, 1e-15);  // phi = 1 at the target
    EXPECT_NEAR(target.weight, 1.5 * 0.5 / 2, 1e-15);
    EXPECT_LT(g.norm(), 1e-13);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    for (int k = 0; k < 50; ++k) {
        Mat3 z = y;
        for (int a = 0; a < 3; ++a) z.col(a) += Vec3(u(rng), u(rng), 0);  // in the plane
        EXPECT_GT(triangle_energy(z, up, target, {0.8, 0}), e);
    }
}

TEST(TriangleEnergy, IsMeasuredInTheTangentPlane) {
    // Moving vertices along n changes nothing; the area is signed against n.
    std::mt19937 rng(5);
    for (int k = 0; k < 20; ++k) {
        const Mat3 y = random_triangle(rng, 0.2);
        Mat3 lifted = y;
        lifted.row(2) += Eigen::RowVector3d(0.3, -0.7, 1.1);
        EXPECT_NEAR(triangle_energy(lifted, up, target, {0.8, 0.1}),
                    triangle_energy(y, up, target, {0.8, 0.1}), 1e-12);
        EXPECT_NEAR(triangle_det(y, up, target), -triangle_det(y, -up, target), 1e-15);
        EXPECT_NEAR(triangle_det(y, 7 * up, target), triangle_det(y, up, target), 1e-15);
    }
    EXPECT_NEAR(triangle_det(corner_triangle(3, 1), up, target), 4.0,
                1e-14);  // area ratio 1.5 / 0.375
}

TEST(TriangleEnergy, InvariantUnderRotationAndTranslation) {
    std::mt19937 rng(7);
    for (int k = 0; k < 20; ++k) {
        const Mat3 y = random_triangle(rng, 0.3);
        const Mat3 r = Eigen::AngleAxisd(0.3 + k, Vec3(1, 2, 3).normalized()).toRotationMatrix();
        Mat3 z = r * y;
        z.colwise() += Vec3(5, -1, 2);
        for (double eps : {0.0, 0.1}) {
            if (triangle_det(y, up, target) <= 0 && eps == 0) continue;
            EXPECT_NEAR(triangle_energy(z, r * up, target, {0.8, eps}),
                        triangle_energy(y, up, target, {0.8, eps}), 1e-12);
        }
    }
}

TEST(TriangleEnergy, GradientMatchesFiniteDifferences) {
    std::mt19937 rng(11);
    const Vec3 n = Vec3(0.2, -0.3, 1).normalized();
    for (int k = 0; k < 30; ++k) {
        const Mat3 y = random_triangle(rng, 0.6);  // some folded
        for (double eps : {0.0, 0.05, 0.5}) {
            const EnergyParams p{0.7, eps};
            Mat3 g;
            const double e = triangle_energy_gradient(y, n, target, p, g);
            if (!std::isfinite(e)) {
                EXPECT_EQ(eps, 0.0);
                EXPECT_LE(triangle_det(y, n, target), 0);
                continue;
            }
            EXPECT_LT((g - fd_gradient(y, n, target, p, 1e-6)).norm(), 1e-6 * (1 + g.norm()))
                << k << " " << eps;
            EXPECT_LT(
                std::abs(g.row(0).sum()) + std::abs(g.row(1).sum()) + std::abs(g.row(2).sum()),
                1e-12 * (1 + g.norm()));
            EXPECT_LT((n.transpose() * g).norm(), 1e-12 * (1 + g.norm()));  // no push off the plane
        }
    }
}

TEST(TriangleEnergy, ExactHessianMatchesFiniteDifferences) {
    std::mt19937 rng(13);
    const Vec3 n = Vec3(-0.4, 0.1, 1).normalized();
    for (int k = 0; k < 30; ++k) {
        const Mat3 y = random_triangle(rng, 0.6);
        const EnergyParams p{0.8, 0.2};
        Mat3 g;
        Mat9 h;
        ASSERT_TRUE(std::isfinite(triangle_energy_hessian(y, n, target, p, g, h, false)));
        const double step = 1e-6;
        Mat9 fd;
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) {
                Mat3 yp = y, ym = y, gp, gm;
                yp(c, a) += step;
                ym(c, a) -= step;
                triangle_energy_gradient(yp, n, target, p, gp);
                triangle_energy_gradient(ym, n, target, p, gm);
                const Mat3 column = (gp - gm) / (2 * step);
                fd.col(3 * a + c) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(column.data());
            }
        EXPECT_LT((h - fd).norm(), 1e-5 * (1 + h.norm())) << k;
        EXPECT_LT((h - h.transpose()).norm(), 1e-12 * (1 + h.norm()));
    }
}

TEST(TriangleEnergy, ProjectedHessianIsPositiveSemiDefiniteAndExactWhereConvex) {
    std::mt19937 rng(17);
    int folded = 0;
    for (int k = 0; k < 200; ++k) {
        const Mat3 y = random_triangle(rng, 0.8);
        folded += triangle_det(y, up, target) <= 0;
        Mat3 g;
        Mat9 h;
        ASSERT_TRUE(std::isfinite(triangle_energy_hessian(y, up, target, {0.8, 0.3}, g, h)));
        Eigen::SelfAdjointEigenSolver<Mat9> eigen(h);
        EXPECT_GT(eigen.eigenvalues()[0], -1e-10 * (1 + h.norm()));
    }
    EXPECT_GT(folded, 10);
    // At the target the exact Hessian is already PSD: the projection leaves it unchanged.
    Mat3 g;
    Mat9 exact, projected;
    triangle_energy_hessian(corner_triangle(1.5, 0.5), up, target, {0.8, 0}, g, exact, false);
    triangle_energy_hessian(corner_triangle(1.5, 0.5), up, target, {0.8, 0}, g, projected, true);
    EXPECT_LT((exact - projected).norm(), 1e-12 * exact.norm());
}

TEST(TriangleEnergy, BarrierIsInfiniteOnFoldedTrianglesAndFiniteWithEps) {
    const Mat3 folded = corner_triangle(1, -1);
    EXPECT_LT(triangle_det(folded, up, target), 0);
    EXPECT_EQ(triangle_energy(folded, up, target, {0.8, 0}),
              std::numeric_limits<double>::infinity());
    const double e = triangle_energy(folded, up, target, {0.8, 0.1});
    EXPECT_TRUE(std::isfinite(e));
    EXPECT_GT(e, triangle_energy(corner_triangle(1, 1), up, target, {0.8, 0.1}));
    EXPECT_TRUE(std::isnan(triangle_energy(corner_triangle(1, 1), Vec3::Zero(), target, {0.8, 0})));
}

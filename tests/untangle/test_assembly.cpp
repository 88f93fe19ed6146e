#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include "grid_problem.h"
#include "untangle/assembly.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

TEST(Assembly, GradientMatchesFiniteDifferencesOfTheSum) {
    const Problem p = test_support::displaced_grid_problem(3, 0.3, 1);
    const Assembly a(p);
    const EnergyParams params{0.8, 0.05};
    std::vector<Vec3> g;
    a.gradient(p.points, params, g);
    std::vector<Vec3> x = p.points;
    for (Id v : {Id(21), Id(22), Id(26), Id(41)}) {
        for (int c = 0; c < 3; ++c) {
            const double h = 1e-6, x0 = x[v][c];
            x[v][c] = x0 + h;
            const double fp = a.energy(x, params);
            x[v][c] = x0 - h;
            const double fm = a.energy(x, params);
            x[v][c] = x0;
            EXPECT_NEAR(g[v][c], (fp - fm) / (2 * h), 1e-5 * (1 + std::abs(g[v][c])));
        }
    }
}

TEST(Assembly, ParallelSumsEqualTheSerialSumAndHessianIsSymmetric) {
    const Problem p = test_support::displaced_grid_problem(8, 0.4, 2);
    const Assembly a(p);
    EXPECT_GT(a.chunks(), 1);
    EXPECT_GT(a.colours(), 1);
    BlockMatrix h = a.empty_hessian();
    std::vector<Vec3> g;
    const EnergyParams params{0.8, 0.1};
    const double f = a.hessian(p.points, params, g, h);
    // Chunks of one colour share no vertex: no update is lost, the sums are the serial ones.
    double serial_f = 0;
    std::vector<Vec3> serial_g(p.points.size(), Vec3::Zero());
    for (Id e = 0; e < p.num_elements(); ++e) {
        const std::array<Id, 4> t = p.element(e);
        Mat34 y, ge;
        for (int c = 0; c < 4; ++c) y.col(c) = p.points[t[c]];
        serial_f += tet_energy_gradient(y, p.target(e), params, ge);
        for (int c = 0; c < 4; ++c) serial_g[t[c]] += ge.col(c);
    }
    EXPECT_NEAR(f, serial_f, 1e-12 * std::abs(serial_f));
    for (size_t v = 0; v < g.size(); ++v) EXPECT_LT((g[v] - serial_g[v]).norm(), 1e-10 * (1 + serial_g[v].norm()));
    for (Id r = 0; r < h.rows(); ++r)
        for (Id m = h.row_start[r]; m < h.row_start[r + 1]; ++m) {
            const Id t = h.find(h.col[m], r);
            ASSERT_GE(t, 0);
            // Blocks are stored in single precision: symmetric to its rounding.
            EXPECT_LT((h.block[m] - h.block[t].transpose()).norm(), 1e-6 * (1 + h.block[m].norm()));
        }
    // The Hessian product without a matrix equals the assembled one (to single precision).
    std::vector<Vec3> v(p.points.size()), hv, hv_free;
    for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3(std::sin(i), std::cos(3.0 * i), 0.5);
    h.multiply(v, hv);
    a.hessian_product(p.points, params, v, hv_free);
    for (size_t i = 0; i < v.size(); ++i) EXPECT_LT((hv[i] - hv_free[i]).norm(), 1e-5 * (1 + hv[i].norm()));
}

TEST(Assembly, ResultsAreBitwiseIdenticalForOneAndTwoThreads) {
    const Problem p = test_support::displaced_grid_problem(6, 0.5, 3);
    const Assembly a(p);
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Vec3> g;
        const double f = a.gradient(p.points, {0.8, 0.1}, g);
        return std::make_pair(f, g);
    };
    const auto one = run(1), two = run(2);
    EXPECT_EQ(one.first, two.first);
    EXPECT_EQ(one.second, two.second);
}

// grid_convergence against the worked example of Celik et al. (2008); order_warning.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "hexmesh/pipeline/grid_convergence.h"

using namespace hexmesh;

namespace {

// Celik, Ghia, Roache, Freitas, Coleman, Raad, "Procedure for Estimation and Reporting of
// Uncertainty Due to Discretization in CFD Applications", J. Fluids Eng. 130 (2008) 078001,
// Table 1, first column (phi = dimensionless reattachment length, 2D grids of N1 = 18000,
// N2 = 8000, N3 = 4500 cells: r21 = sqrt(18000/8000) = 1.5, r32 = sqrt(8000/4500) = 1.333).
// Published results: p = 1.53, phi_ext^21 = 6.1685, e_a^21 = 1.5 %, e_ext^21 = 1.7 %,
// GCI_fine^21 = 2.2 %. (The same inputs give p = 1.53397 in the test suite of
// github.com/oscar-monsalve/GCI, tests/test_2d_p_value_monotonic.py.)
GridConvergenceInput celik_table_1() {
    GridConvergenceInput in;
    in.phi1 = 6.063, in.phi2 = 5.972, in.phi3 = 5.863;
    in.r21 = std::sqrt(18000.0 / 8000.0);
    in.r32 = std::sqrt(8000.0 / 4500.0);
    return in;
}

// Relative agreement to 3 significant digits.
void expect_3_digits(double value, double published) {
    EXPECT_NEAR(value, published, 0.5e-2 * std::abs(published)) << value << " vs " << published;
}

}  // namespace

TEST(GridConvergence, ObservedOrderOfCelikTable1) {
    const GridConvergence g = grid_convergence(celik_table_1());
    expect_3_digits(g.order, 1.53);
    EXPECT_GT(g.iterations, 0);  // r21 != r32: the fixed-point iteration ran
    EXPECT_FALSE(g.oscillatory);
}

TEST(GridConvergence, ExtrapolatedValueOfCelikTable1) {
    EXPECT_NEAR(grid_convergence(celik_table_1()).extrapolated, 6.1685, 1e-3);
}

TEST(GridConvergence, RelativeErrorsAndGciOfCelikTable1) {
    const GridConvergence g = grid_convergence(celik_table_1());
    EXPECT_NEAR(100 * g.relative_error, 1.50, 0.005);
    EXPECT_NEAR(100 * g.extrapolated_relative_error, 1.7, 0.05);
    EXPECT_NEAR(100 * g.gci_fine, 2.2, 0.05);
    expect_3_digits(100 * g.gci_fine, 2.18);  // 1.25 * 1.501 % / (1.5^1.534 - 1)
}

TEST(GridConvergence, OscillatoryValuesUseSignMinusOne) {
    // Oscillatory inputs (s = -1) of the test suite of github.com/oscar-monsalve/GCI,
    // tests/test_2d_p_value_oscillatory.py: 2D grids of N = 18000, 4500, 980 cells; it
    // expects p = 1.50769 from the same fixed-point iteration.
    GridConvergenceInput in;
    in.phi1 = 6.0042, in.phi2 = 5.9624, in.phi3 = 6.0909;
    in.r21 = std::sqrt(18000.0 / 4500.0), in.r32 = std::sqrt(4500.0 / 980.0);
    const GridConvergence g = grid_convergence(in);
    EXPECT_TRUE(g.oscillatory);
    EXPECT_NEAR(g.order, 1.50769, 1e-4);
}

TEST(GridConvergence, EqualRatiosGiveTheClosedForm) {
    // Second-order data on ratio 2: phi = 1 + h^2 for h = 1, 2, 4.
    GridConvergenceInput in;
    in.phi1 = 2, in.phi2 = 5, in.phi3 = 17;
    const GridConvergence g = grid_convergence(in);
    EXPECT_NEAR(g.order, 2, 1e-12);
    EXPECT_NEAR(g.extrapolated, 1, 1e-12);
    EXPECT_EQ(g.iterations, 0);
}

TEST(GridConvergence, ZeroDifferencesAreRefused) {
    GridConvergenceInput in;
    in.phi1 = 1, in.phi2 = 1, in.phi3 = 2;
    EXPECT_THROW(grid_convergence(in), std::invalid_argument);
    in.phi1 = 0.5, in.phi2 = 2, in.phi3 = 2;
    EXPECT_THROW(grid_convergence(in), std::invalid_argument);
}

TEST(GridConvergence, RatiosNotAboveOneAreRefused) {
    GridConvergenceInput in = celik_table_1();
    in.r21 = 1;
    EXPECT_THROW(grid_convergence(in), std::invalid_argument);
}

TEST(OrderWarning, NoneBetweenHalfAndTwiceTheFormalOrder) {
    EXPECT_EQ(order_warning(2.0, 2), "");
    EXPECT_EQ(order_warning(1.0, 2), "");
    EXPECT_EQ(order_warning(4.0, 2), "");
    EXPECT_EQ(order_warning(1.53, 2), "");  // Celik's Table 1
}

TEST(OrderWarning, FarBelowTheFormalOrderIsNotAsymptotic) {
    // phi = 1, 1.1, 1.21975 on ratio 2: p = log2(1.1975) = 0.26 for a second-order scheme.
    GridConvergenceInput in;
    in.phi1 = 1, in.phi2 = 1.1, in.phi3 = 1.21975;
    const GridConvergence g = grid_convergence(in);
    EXPECT_NEAR(g.order, 0.26, 1e-3);
    const std::string w = order_warning(g.order, 2);
    EXPECT_NE(w.find("p = 0.26 is below 0.5 times the formal order 2 (p < 1)"), std::string::npos)
        << w;
    EXPECT_NE(w.find("not in the asymptotic range"), std::string::npos) << w;
    EXPECT_EQ(order_warning(g.order, 0.5), "");  // in range for a scheme of order 0.5
}

TEST(OrderWarning, FarAboveTheFormalOrderIsNotAsymptotic) {
    const std::string w = order_warning(2.6, 1);
    EXPECT_NE(w.find("p = 2.6 is above 2 times the formal order 1 (p > 2)"), std::string::npos)
        << w;
    EXPECT_NE(w.find("not in the asymptotic range"), std::string::npos) << w;
    EXPECT_EQ(order_warning(2.6, 1, {0.5, 3}), "");  // a wider range, as given
}

TEST(OrderWarning, NotFiniteIsWarnedAbout) {
    for (const double p : {std::nan(""), HUGE_VAL}) {
        const std::string w = order_warning(p, 2);
        EXPECT_NE(w.find("is not a finite number"), std::string::npos) << w;
        EXPECT_NE(w.find("not in the asymptotic range"), std::string::npos) << w;
    }
}

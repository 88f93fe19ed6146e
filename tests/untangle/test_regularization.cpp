#include <gtest/gtest.h>

#include <cmath>

#include "untangle/regularization.h"

using hexmesh::untangle::chi;
using hexmesh::untangle::chi_derivative;

TEST(Chi, PositiveForEveryDeterminant) {
    for (double d : {-1e6, -10.0, -1.0, -1e-3, 0.0, 1e-3, 1.0, 1e6})
        EXPECT_GT(chi(d, 1e-3), 0.0) << "d = " << d;
}

TEST(Chi, MatchesTheDefinitionWhereItIsWellConditioned) {
    for (double d : {-0.5, -0.1, 0.0, 0.2, 3.0}) {
        const double eps = 0.3;
        EXPECT_NEAR(chi(d, eps), 0.5 * (d + std::sqrt(eps * eps + d * d)), 1e-15);
    }
}

TEST(Chi, NoCancellationForLargeNegativeDeterminants) {
    // Naive (d + sqrt(eps^2 + d^2)) / 2 returns 0 here; the true value is ~eps^2 / (4 |d|).
    const double d = -1e8, eps = 1e-4;
    EXPECT_NEAR(chi(d, eps) / (eps * eps / (4 * std::abs(d))), 1.0, 1e-12);
}

TEST(Chi, TendsToPositivePartAsEpsVanishes) {
    EXPECT_NEAR(chi(2.0, 1e-9), 2.0, 1e-15);
    EXPECT_LT(chi(-2.0, 1e-9), 1e-18);
}

TEST(Chi, DerivativeMatchesFiniteDifferences) {
    for (double eps : {1e-2, 0.5})
        for (double d : {-3.0, -0.4, -1e-3, 0.0, 1e-3, 0.7, 5.0}) {
            const double step = 1e-6 * std::max(1.0, std::abs(d));
            const double fd = (chi(d + step, eps) - chi(d - step, eps)) / (2 * step);
            EXPECT_NEAR(chi_derivative(d, eps), fd, 1e-6) << "d = " << d << " eps = " << eps;
        }
}

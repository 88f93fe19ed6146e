// Shared helpers of the surface tests: seeded random points and finite-difference checks.
#pragma once

#include <cmath>
#include <random>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh::test {

inline Vec3 random_in_box(std::mt19937& rng, const Vec3& lo, const Vec3& hi) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    return lo + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(hi - lo);
}

inline Vec3 random_unit_vector(std::mt19937& rng) {
    std::normal_distribution<double> normal(0.0, 1.0);
    Vec3 v;
    do v = Vec3(normal(rng), normal(rng), normal(rng));
    while (v.norm() < 1e-6);
    return v.normalized();
}

// Central differences of u.value with step h, independent of u.gradient.
inline Vec3 central_difference(const ImplicitFunction& u, const Vec3& p, double h = 1e-6) {
    Vec3 g;
    for (int a = 0; a < 3; ++a) {
        const Vec3 e = h * Vec3::Unit(a);
        g[a] = (u.value(p + e) - u.value(p - e)) / (2 * h);
    }
    return g;
}

// True when no kink of u lies within `reach` of p along a coordinate axis: the second
// differences stay at the size a smooth function with curvature < 1/reach would give.
inline bool smooth_near(const ImplicitFunction& u, const Vec3& p, double reach = 1e-3) {
    const double f = u.value(p);
    for (int a = 0; a < 3; ++a) {
        const Vec3 e = reach * Vec3::Unit(a);
        if (std::abs(u.value(p + e) - 2 * f + u.value(p - e)) > 10 * reach * reach) return false;
    }
    return true;
}

}  // namespace hexmesh::test

// The chi regularization of the determinant that makes the functional finite on tangled meshes.
#pragma once

#include <cmath>

namespace hexmesh::untangle {

// r = sqrt(eps^2 + d^2), without overflow for huge |d|.
inline double regularization_radius(double d, double eps) {
    return std::abs(d) < 1e100 ? std::sqrt(eps * eps + d * d) : std::hypot(eps, d);
}

// chi(d, eps) = (d + sqrt(eps^2 + d^2)) / 2: > 0 for every d when eps > 0, -> max(d, 0) as
// eps -> 0. For d <= 0 it is evaluated as eps^2 / (2 (sqrt(eps^2 + d^2) - d)), which has no
// cancellation (docs/architecture.md#the-functional). r is regularization_radius(d, eps).
inline double chi(double d, double eps, double r) {
    return d > 0 ? 0.5 * (d + r) : eps * eps / (2 * (r - d));
}
inline double chi(double d, double eps) {
    return chi(d, eps, regularization_radius(d, eps));
}

// d chi / d d = (1 + d / sqrt(eps^2 + d^2)) / 2, in (0, 1]; for d < 0 evaluated as
// eps^2 / (2 r (r - d)) with r = sqrt(eps^2 + d^2), free of cancellation.
inline double chi_derivative(double d, double eps, double r) {
    return d > 0 ? 0.5 * (1 + d / r) : eps * eps / (2 * r * (r - d));
}
inline double chi_derivative(double d, double eps) {
    return chi_derivative(d, eps, regularization_radius(d, eps));
}

}  // namespace hexmesh::untangle

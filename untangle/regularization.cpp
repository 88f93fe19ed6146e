#include "untangle/regularization.h"

#include <cmath>

namespace hexmesh::untangle {

double chi(double d, double eps) {
    const double r = std::hypot(eps, d);
    return d > 0 ? 0.5 * (d + r) : eps * eps / (2 * (r - d));
}

double chi_derivative(double d, double eps) {
    const double r = std::hypot(eps, d);
    return d > 0 ? 0.5 * (1 + d / r) : eps * eps / (2 * r * (r - d));
}

}  // namespace hexmesh::untangle

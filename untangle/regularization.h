// The chi regularization of the determinant that makes the functional finite on tangled meshes.
#pragma once

namespace hexmesh::untangle {

// chi(d, eps) = (d + sqrt(eps^2 + d^2)) / 2: > 0 for every d when eps > 0, -> max(d, 0) as
// eps -> 0. For d <= 0 it is evaluated as eps^2 / (2 (sqrt(eps^2 + d^2) - d)), which has no
// cancellation (DESIGN §4).
double chi(double d, double eps);

// d chi / d d = (1 + d / sqrt(eps^2 + d^2)) / 2, in (0, 1]; for d < 0 evaluated as
// eps^2 / (2 r (r - d)) with r = sqrt(eps^2 + d^2), free of cancellation.
double chi_derivative(double d, double eps);

}  // namespace hexmesh::untangle

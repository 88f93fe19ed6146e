// The 2D energy of a surface triangle, measured in the tangent plane of u = 0
// (docs/architecture.md#the-functional).
#pragma once

#include <Eigen/Core>

#include "hexmesh/core/types.h"
#include "untangle/tet_energy.h"

namespace hexmesh::untangle {

using Mat2 = Eigen::Matrix2d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// Parameters of one surface triangle: target inverse H^-1 (H = [z1-z0, z2-z0] of the target
// triangle in its own plane), weight w (the target area by default: det H / 2) and target
// area ratio v0.
struct TriangleTarget {
    Mat2 inverse = Mat2::Identity();
    double weight = 0.5;
    double v0 = 1;
};

// For a triangle with vertices y (columns) near a surface of unit normal n: its edges
// E = [y1 - y0, y2 - y0] in the tangent plane, Q = [t1 t2]^T E with (t1, t2, n) a
// right-handed orthonormal frame, and S = Q H^-1. det S = n . (e1 x e2) / det H is the
// signed area ratio against n: > 0 when the triangle turns counter-clockwise seen from the
// side n points to. The energy is the 2D analogue of the tet's,
//   phi(S) = theta mu + (1 - theta) nu,  nu = tr(S^T S) / (2 det S),
//   mu = (v0 / det S + det S / v0) / 2,
// with det S replaced by chi(det S, eps) in every term when eps > 0. nu >= 1 with equality
// iff S is a similarity; phi = 1 at S = I when v0 = 1. n is a parameter: the derivatives
// below are those of the energy with n held fixed (it comes from grad u, not from y).

// det S of the triangle (<= 0: folded against n), the same expression as in the energy so
// that both agree on the sign. n need not be unit (zero: NaN).
double triangle_det(const Mat3& y, const Vec3& n, const TriangleTarget& t);

// w phi(S); +infinity when eps = 0 and det S <= 0, NaN when n = 0 or y is not finite.
double triangle_energy(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                       const EnergyParams& p);

// Value and gradient (column a = dE/dy_a, in the tangent plane). `grad` is left
// unspecified when the value is not finite.
double triangle_energy_gradient(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                                const EnergyParams& p, Mat3& grad);

// Value, gradient and the 9 x 9 Hessian (vertex-major: row 3a + c), with its negative
// eigenvalues in S clamped to zero (project_psd = false: the exact Hessian). `grad` and
// `hess` are left unspecified when the value is not finite.
double triangle_energy_hessian(const Mat3& y, const Vec3& n, const TriangleTarget& t,
                               const EnergyParams& p, Mat3& grad, Mat9& hess,
                               bool project_psd = true);

// The target of the right-angle corner of a rectangle with edges (a, b) along the
// triangle's first and second edge (quad corner triangles), v0 = 1, weight the area a b / 2.
inline TriangleTarget rectangle_corner_target(double a, double b) {
    TriangleTarget t;
    t.inverse = Eigen::Vector2d(1 / a, 1 / b).asDiagonal();
    t.weight = a * b / 2;
    return t;
}

}  // namespace hexmesh::untangle

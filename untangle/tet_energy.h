// The per-tetrahedron distortion energy phi = theta mu + (1 - theta) nu and its derivatives.
#pragma once

#include <Eigen/Core>
#include <array>

#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

using Mat34 = Eigen::Matrix<double, 3, 4>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat38 = Eigen::Matrix<double, 3, 8>;

// Parameters of one element: target inverse H^-1 (H = [z1-z0, z2-z0, z3-z0] of the target
// tet), weight w = det H / 6 and target volume ratio v0 (DESIGN §4).
struct TetTarget {
    Mat3 inverse = Mat3::Identity();
    double weight = 1.0 / 6;
    double v0 = 1;
};

// Continuation state shared by all elements: theta weighs volume against shape; eps > 0
// regularizes det S by chi (untangling), eps = 0 is the pure barrier (F = +inf if det <= 0).
struct EnergyParams {
    double theta = 0.8;
    double eps = 0;
};

// det S of the element with vertices y (columns), S = Q H^-1.
double tet_det(const Mat34& y, const TetTarget& t);

// w phi(S). With eps = 0 and det S <= 0 the value is +infinity.
double tet_energy(const Mat34& y, const TetTarget& t, const EnergyParams& p);

// Value and gradient (column a = dE/dy_a). Returns the value; `grad` is left unspecified
// when the value is infinite.
double tet_energy_gradient(const Mat34& y, const TetTarget& t, const EnergyParams& p,
                           Mat34& grad);

// Value, gradient and a positive semi-definite 12 x 12 Hessian (vertex-major: row 3a + c),
// obtained by clamping the negative eigenvalues of the 9 x 9 Hessian in S (known in closed
// form) to zero
// (project_psd = false gives the exact, possibly indefinite, Hessian).
double tet_energy_hessian(const Mat34& y, const TetTarget& t, const EnergyParams& p,
                          Mat34& grad, Mat12& hess, bool project_psd = true);

// The sum of the energies of the 8 corner tets of a hex (columns of y: its nodes in VTK
// order) whose targets are the corners of a box with edge lengths `edges` along the hex's
// local x, y, z (hex_corner_target), and with `grad` its gradient (column a = dE/dy_a):
// the same values as tet_energy_gradient on each corner, computed without matrix products
// and with each node loaded once. +infinity when eps = 0 and a corner has det S <= 0.
double hex_energy(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad = nullptr);

// The target of a regular tet of edge `edge`, and of the right-angle corner of an axis-aligned
// box with edges (a, b, c) (hex corner tets), each with v0 = 1.
TetTarget regular_tet_target(double edge);
inline TetTarget box_corner_target(const Vec3& edges) {
    return {Mat3(edges.cwiseInverse().asDiagonal()), edges.prod() / 6, 1};
}

}  // namespace hexmesh::untangle

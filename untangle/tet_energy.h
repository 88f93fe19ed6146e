// The per-tetrahedron distortion energy phi = theta mu + (1 - theta) nu and its derivatives.
#pragma once

#include <Eigen/Core>
#include <array>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

using Mat34 = Eigen::Matrix<double, 3, 4>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat38 = Eigen::Matrix<double, 3, 8>;
// A tet's Hessian as 4 x 4 blocks: block[a][b] = d2E / dy_a dy_b.
using TetBlocks = std::array<std::array<Mat3, 4>, 4>;

// Parameters of one element: target inverse H^-1 (H = [z1-z0, z2-z0, z3-z0] of the target
// tet), weight w = det H / 6 and target volume ratio v0 (docs/architecture.md#the-functional).
struct TetTarget {
    Mat3 inverse = Mat3::Identity();
    double weight = 1.0 / 6;
    double v0 = 1;
};

// The volume weight theta of the functional θ·volume + (1 − θ)·shape as the method publishes
// it (docs/architecture.md#the-functional): the untangler's default when it optimizes. `run`
// weighs shape more (its case file's solver.theta), tets too (tet_untangle_options).
inline constexpr double default_theta = 0.8;

// Continuation state shared by all elements: theta weighs volume against shape; eps > 0
// regularizes det S by chi (untangling), eps = 0 is the pure barrier (F = +inf if det <= 0).
struct EnergyParams {
    double theta = default_theta;
    double eps = 0;
    // Every tet (plain or a hex's corner) weighs as a unit target, w = 1/6, instead of its
    // target's volume; surface triangles keep their area. Applied by Assembly, not by the
    // kernels below, which always return w phi with the target's own w.
    bool equal_weights = false;
};

// det S of the element with vertices y (columns), S = Q H^-1.
double tet_det(const Mat34& y, const TetTarget& t);

// w phi(S). With eps = 0 and det S <= 0 the value is +infinity.
double tet_energy(const Mat34& y, const TetTarget& t, const EnergyParams& p);

// Value and gradient (column a = dE/dy_a). Returns the value; `grad` is left unspecified
// when the value is infinite.
double tet_energy_gradient(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat34& grad);

// Value, gradient and a positive semi-definite 12 x 12 Hessian (vertex-major: row 3a + c),
// obtained by clamping the negative eigenvalues of the 9 x 9 Hessian in S (known in closed
// form) to zero
// (project_psd = false gives the exact, possibly indefinite, Hessian).
double tet_energy_hessian(const Mat34& y, const TetTarget& t, const EnergyParams& p, Mat34& grad,
                          Mat12& hess, bool project_psd = true);

// The sum of the energies of the 8 corner tets of a hex (columns of y: its nodes in VTK
// order) whose targets are the corners of a box with edge lengths `edges` along the hex's
// local x, y, z (hex_corner_target), and with `grad` its gradient (column a = dE/dy_a):
// the same values as tet_energy_gradient on each corner (to rounding), computed without
// matrix products, four corners at a time in vector lanes (built for AVX2 too, and run so
// where the CPU has it: the same bits). +infinity when eps = 0 and a corner has det S <= 0.
double hex_energy(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad = nullptr);

// The node pairs (a <= b) of a hex that share one of its corner tets: the 8 diagonals, the
// 12 edges and the 12 face diagonals are there, the 4 body diagonals are not.
inline constexpr std::array<std::array<int, 2>, 32> hex_hessian_pairs = [] {
    std::array<std::array<int, 2>, 32> pairs{};
    bool used[8][8] = {};
    int n = 0;
    for (const auto& t : hex_corner_tets)
        for (int a : t)
            for (int b : t) {
                const int lo = a < b ? a : b, hi = a < b ? b : a;
                if (!used[lo][hi]) used[lo][hi] = true, pairs[n++] = {lo, hi};
            }
    return pairs;
}();

// The Hessian of a hex's corner-tet energy between its nodes: block[a][b] (3 x 3) for the
// pairs of hex_hessian_pairs (a <= b); the other blocks are left unset.
struct HexHessian {
    std::array<std::array<Mat3, 8>, 8> block;
};

// hex_energy with the PSD-projected Hessian of every corner tet summed into `hess`: the
// same blocks as tet_energy_hessian on each corner. `grad` and `hess` are left unspecified
// when the value is infinite.
double hex_energy_hessian(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38& grad,
                          HexHessian& hess);

// hex_energy (with `hess`: hex_energy_hessian, and then `grad` is required) as built for
// baseline x86-64, whatever the CPU runs: to check that the AVX2 build changes no bits.
double hex_energy_baseline(const Mat38& y, const Vec3& edges, const EnergyParams& p, Mat38* grad,
                           HexHessian* hess = nullptr);

// The target of a regular tet of edge `edge`, and of the right-angle corner of an axis-aligned
// box with edges (a, b, c) (hex corner tets), each with v0 = 1.
TetTarget regular_tet_target(double edge);
inline TetTarget box_corner_target(const Vec3& edges) {
    return {Mat3(edges.cwiseInverse().asDiagonal()), edges.prod() / 6, 1};
}

}  // namespace hexmesh::untangle

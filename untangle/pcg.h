// Preconditioned conjugate gradients on vectors of 3D vertex values.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

using VertexVector = std::vector<Vec3>;
using LinearOperator = std::function<void(const VertexVector& in, VertexVector& out)>;

struct PcgResult {
    int iterations = 0;
    double relative_residual = 0;
};

// Solves A x = b for symmetric positive (semi-)definite A, from x = 0, until
// |r| <= tolerance |b| or max_iterations. `precondition` applies M^-1 (identity if empty).
// Stops early, keeping the last iterate, if A shows a direction of non-positive curvature.
PcgResult solve_pcg(const LinearOperator& apply_a, const LinearOperator& precondition,
                    const VertexVector& b, VertexVector& x, double tolerance, int max_iterations);

// The same with M^-1 given as one 3 x 3 block per vertex (block Jacobi; Jacobi when the
// blocks are diagonal), in single precision, applied in the pass that also takes its dot
// product with the residual.
using BlockInverse = std::vector<Eigen::Matrix3f>;
PcgResult solve_pcg(const LinearOperator& apply_a, const BlockInverse& precondition,
                    const VertexVector& b, VertexVector& x, double tolerance, int max_iterations);

// Deterministic dot product of two vertex vectors (fixed split, whatever the thread count).
double dot(const VertexVector& a, const VertexVector& b);

}  // namespace hexmesh::untangle

// The signed SVD of a 3 x 3 matrix, S = U diag(sigma) V^T with U and V rotations.
#pragma once

#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

// Signed SVD S = U diag(sigma) V^T with U, V rotations (sigma[2] < 0 when det S < 0), from
// the closed-form eigensystem of S^T S: V its eigenvectors (largest first), U by
// Gram-Schmidt on S V, sigma the diagonal of U^T S V. Accurate where the singular values are
// apart; where they nearly coincide any basis of their space is a valid choice.
void signed_svd(const Mat3& s, Mat3& u, Vec3& sigma, Mat3& v);

}  // namespace hexmesh::untangle

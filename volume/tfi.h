// Transfinite interpolation: interior nodes of a structured block from its six faces.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Sets every interior node of `block` (0 < i < ni-1, same for j, k) in `points` from the
// block's boundary nodes by trilinear transfinite interpolation (Gordon-Hall: faces minus
// edges plus corners). Blending parameters follow the normalized arc length of the block's
// 12 edges, so stretching on the boundary carries into the interior. Boundary nodes are
// left untouched; the result reproduces any grid that is trilinear in its parameters.
void fill_interior_tfi(const Block& block, std::vector<Vec3>& points);

// Carries the interior nodes of `block` along with its boundary nodes, which have moved from
// `before` (#V, the positions they had) to `points`: each interior node moves by the
// difference between the interpolations above of the boundary now and before, so a uniform
// shift of the boundary shifts every node by the same amount and a boundary that did not
// move moves nothing. Boundary nodes are left as they are.
void carry_interior_tfi(const Block& block, const std::vector<Vec3>& before,
                        std::vector<Vec3>& points);

}  // namespace hexmesh

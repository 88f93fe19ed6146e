// Grids built by hand for the tests: small shapes that fail one check on purpose.
#pragma once

#include "hexmesh/core/block_grid.h"

namespace hexmesh::test {

// Two slanted cells one above the other, a chevron of parallelepipeds (every corner tet and face
// pyramid positive) 0.1 thick along x, the top and bottom faces shifted `lean` along x from the
// shared one: the cells' centres, 1 apart, lie on a line lean / 2 from the shared face's centre,
// and the face is 0.1 wide that way, so its skewness (and the top and bottom faces') is
// (lean / 2) / 0.2.
inline BlockGrid leaning_cells(double lean) {
    BlockGrid grid;
    for (int k = 0; k <= 2; ++k)
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= 1; ++i)
                grid.points.emplace_back(0.1 * i + lean * (k == 1 ? 0.0 : 1.0), j, k - 1.0);
    grid.kinds.assign(grid.points.size(), VertexKind::fixed);
    Block b;
    b.name = "leaning";
    b.nodes = {2, 2, 3};
    for (Id n = 0; n < 12; ++n) b.node_ids.push_back(n);
    b.face_patch = {"walls", "walls", "walls", "walls", "walls", "walls"};
    grid.blocks = {b};
    return grid;
}

}  // namespace hexmesh::test

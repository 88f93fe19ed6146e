// Shared checks of block grids used by the volume tests.
#pragma once

#include <algorithm>
#include <array>
#include <map>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/reference_hex.h"

namespace hexmesh::test_support {

// Number of hex faces used by exactly one cell (boundary) and by more than two (broken).
struct FaceCounts {
    Id boundary = 0, internal = 0, over_shared = 0;
};

inline FaceCounts count_faces(const HexMesh& mesh) {
    std::map<std::array<Id, 4>, int> uses;
    for (Id c = 0; c < mesh.num_cells(); ++c)
        for (const auto& f : hex_faces) {
            std::array<Id, 4> key{mesh.node(c, f[0]), mesh.node(c, f[1]), mesh.node(c, f[2]),
                                  mesh.node(c, f[3])};
            std::sort(key.begin(), key.end());
            ++uses[key];
        }
    FaceCounts counts;
    for (const auto& [key, n] : uses) {
        (void)key;
        if (n == 1) ++counts.boundary;
        else if (n == 2) ++counts.internal;
        else ++counts.over_shared;
    }
    return counts;
}

}  // namespace hexmesh::test_support

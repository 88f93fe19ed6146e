// Shared checks of block grids, and a body with sharp creases, used by the volume tests.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <memory>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/reference_hex.h"
#include "surface/analytic.h"
#include "surface/csg.h"

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
        if (n == 1)
            ++counts.boundary;
        else if (n == 2)
            ++counts.internal;
        else
            ++counts.over_shared;
    }
    return counts;
}

// The body of cases/box_cylinder centred on its box: the box [-1, 1]^2 x [-0.6, 0.6] and a
// cylinder of radius 0.6 on the z axis from z = -0.2 to 1.2, whose rim (z = 1.2) and junction
// with the box (z = 0.6) are circles around the axis.
inline Body box_with_cylinder() {
    return std::make_shared<Csg>(
        CsgOp::Union, std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(1.0, 1.0, 0.6)),
                                        std::make_shared<Cylinder>(Vec3(0, 0, 0.5), 0.6, 0.7)});
}

}  // namespace hexmesh::test_support

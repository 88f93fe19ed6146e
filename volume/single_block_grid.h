// A single structured block fitted to a body: its bounding box mapped onto u = 0.
#pragma once

#include <array>
#include <optional>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "volume/stretching.h"

namespace hexmesh {

struct SingleBlockOptions {
    std::array<int, 3> cells = {20, 20, 20};  // cells along x, y, z
    WallLayers wall_layers;      // law at both ends of every grid line (layers = 0: uniform)
    std::optional<Vec3> centre;  // default: centre of the body's bounds
};

// One block "body": the lattice of the body's bounding box (distributions from the wall law
// at both ends of each axis), boundary nodes projected radially from the centre onto
// u = 0 (kind slip), interior filled by TFI. Suited to box-like bodies; on smooth bodies the
// cells along the 12 box edges flatten (see docs/architecture.md#construction), which the O-H grid
// avoids.
BlockGrid make_single_block_grid(const ImplicitFunction& body, const SingleBlockOptions& options);

// Positions of cells+1 nodes on [0, length] with the wall law applied from both ends.
std::vector<double> two_sided_distances(double length, int cells, const WallLayers& law);

}  // namespace hexmesh

// The nodes of an O-grid's lines from each wall node to its far-field node, leaving along the
// wall normal and bending towards the straight direction.
#pragma once

#include <functional>
#include <vector>

#include "hexmesh/core/types.h"
#include "volume/cube_sphere.h"
#include "volume/stretching.h"

namespace hexmesh {

// The nk - 1 inner nodes of every line from its wall node along its unit normal, bending
// towards its far-field node (make_o_grid without paths), handed to set_line(s, x) with x[0]
// the wall node and x[nk] the far-field node. reach: the length of the wall node's
// unit_offset (volume/wall_lines.h), 1 on a smooth wall; on a body with creases (some reach
// above 1) every line has turned straight within half the bounds' `diagonal` of the wall.
void place_nodes_on_lines(const CubeSurfaceLattice& surface, const std::vector<Vec3>& wall,
                          const std::vector<Vec3>& normal, const std::vector<double>& reach,
                          const std::vector<Vec3>& far, double diagonal, int nk,
                          const WallLayers& law,
                          const std::function<void(Id, const std::vector<Vec3>&)>& set_line);

}  // namespace hexmesh

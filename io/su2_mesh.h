// SU2 native mesh writer (.su2, ASCII) for block grids with named boundary patches.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as an SU2 mesh: NDIME= 3; NELEM hexahedra (VTK type 12, node order = VTK's,
// each followed by its index) in to_hex_mesh order; NPOIN points (0-based, each followed by its
// index); NMARK markers, one per boundary patch (MARKER_TAG = the patch's name), each with its
// quadrilaterals (VTK type 9) oriented outwards. Throws std::runtime_error on a write error.
void write_su2_mesh(const BlockGrid& grid, const std::string& path);

}  // namespace hexmesh

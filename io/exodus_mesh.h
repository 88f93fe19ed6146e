// Exodus II writer (.exo, netCDF) for block grids with named boundary patches.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as an Exodus II file (netCDF, 64-bit offset): the points (coordx, coordy,
// coordz), one element block "fluid" of HEX8 elements (node order = VTK's, which is Exodus's;
// elements in to_hex_mesh order) and one side set per boundary patch, named after it, each
// face as its element and the element's side (Exodus numbering: 1 = nodes 1 2 6 5, ...,
// 5 = 1 4 3 2, 6 = 5 6 7 8). Throws std::runtime_error naming the file on a write error.
void write_exodus_mesh(const BlockGrid& grid, const std::string& path);

}  // namespace hexmesh

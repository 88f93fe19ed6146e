// AFLR3 / FUN3D UGRID writer (.ugrid, ASCII, with its .mapbc) for block grids.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as a formatted (ASCII) UGRID file: the counts line (nodes, 0 boundary triangles,
// boundary quadrilaterals, 0 tets, pyramids and prisms, hexahedra), the points, the boundary
// quadrilaterals (1-based, oriented outwards: each closed surface consistently), their surface
// ids (patch index + 1), then the hexahedra (node order = VTK's, which is UGRID's). Beside it,
// PATH without ".ugrid" + ".mapbc": one line per surface id with its FUN3D boundary condition
// (4000 no-slip wall for "wall", 5050 freestream for the other patches) and the patch's name.
// Throws std::runtime_error on a write error.
void write_ugrid_mesh(const BlockGrid& grid, const std::string& path);

// The .mapbc file written beside a .ugrid file `path`.
std::string ugrid_mapbc_path(const std::string& path);

}  // namespace hexmesh

// Medit .mesh (INRIA, ASCII, MeshVersionFormatted 2) writer and reader for hexahedral grids.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Writes Vertices (reference 0), Quadrilaterals (the boundary faces, oriented outwards,
// reference = patch number from 1) and Hexahedra (VTK node order, reference 1). Medit has no
// patch names: a comment line "# patch N NAME" before the Quadrilaterals lists them.
// Throws std::runtime_error on a write error.
void write_medit_mesh(const BlockGrid& grid, const std::string& path);

// Reads Vertices and Hexahedra (other keywords skipped). Throws InputError on bad input.
HexMesh read_medit_mesh(const std::string& path);

}  // namespace hexmesh

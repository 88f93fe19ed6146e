// Gmsh MSH 4.1 (ASCII) writer and reader for hexahedral grids with named boundary patches.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Writes `grid` as MSH 4.1 ASCII: one volume entity (physical group 3D "fluid") holding every
// node and every hexahedron (type 5, node order = VTK's), and one surface entity per boundary
// patch (physical group 2D named after the patch) holding its quadrangles (type 3), oriented
// outwards. Node tags are grid node ids + 1; hexahedra are tagged 1..#cells in to_hex_mesh
// order, quadrangles after them. Throws std::runtime_error on a write error.
void write_gmsh_mesh(const BlockGrid& grid, const std::string& path);

// Reads the nodes and 8-node hexahedra of an MSH 4.1 ASCII file (other element types are
// skipped). Throws InputError naming the file and what is wrong.
HexMesh read_gmsh_mesh(const std::string& path);

}  // namespace hexmesh

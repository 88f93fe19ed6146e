// Fluent / ANSYS mesh writer (.msh, ASCII) for block grids with named boundary patches.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as a Fluent ASCII mesh: nodes (zone 1), one fluid cell zone of hexahedra
// (zone 2, cells in to_hex_mesh order), the interior faces (zone 3, type interior), then one
// face zone per boundary patch (zone 4, 5, ...: type wall for "wall", pressure-far-field for
// the others), every face as its 4 nodes and its two cells (c0 c1; 0 for none), and a zone
// section (45) naming each zone. Indices are hexadecimal, as Fluent writes them. The
// right-hand rule over a face's nodes points into c0 (boundary faces: into the domain), as
// OpenFOAM's fluent3DMeshToFoam reads it. Throws std::runtime_error on a write error.
void write_fluent_mesh(const BlockGrid& grid, const std::string& path);

}  // namespace hexmesh

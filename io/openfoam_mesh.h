// OpenFOAM polyMesh writer: a block grid as points, faces, owner, neighbour and boundary.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as an OpenFOAM case folder: CASE/constant/polyMesh/{points, faces, owner,
// neighbour, boundary} (ASCII, FoamFile headers) and, so checkMesh runs on it as is, a
// minimal CASE/system. Internal faces come first in upper-triangular order
// (ascending owner, then neighbour), each oriented from owner to neighbour; boundary faces
// follow, grouped by patch, oriented outwards. Patch "wall" has type wall, every other patch
// type patch; faces between blocks without a match go to patch "unassigned". The minimal
// system/{controlDict, fvSchemes, fvSolution} are written only where absent. Throws
// std::runtime_error naming the file on a write error.
void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir);

// The same polyMesh files directly in `polymesh_dir` (created if missing), nothing else.
void write_openfoam_polymesh(const BlockGrid& grid, const std::string& polymesh_dir);

}  // namespace hexmesh

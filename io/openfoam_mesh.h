// OpenFOAM polyMesh writer: a block grid as points, faces, owner, neighbour and boundary.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"
#include "io/flow_spec.h"

namespace hexmesh {

// Writes `grid` as an OpenFOAM case folder that simpleFoam runs as written:
// CASE/constant/polyMesh/{points, faces, owner, neighbour, boundary} (ASCII, FoamFile
// headers), and for `flow` constant/{transportProperties, turbulenceProperties},
// system/{controlDict, fvSchemes, fvSolution} and 0/{U, p} (k, omega and nut for
// k-omega-sst). Points are numbered as the blocks first reach them (block order, i fastest), so
// a grid and the same grid read back from its VTK files give the same files. Internal faces
// come first in upper-triangular order (ascending owner, then neighbour), each oriented from
// owner to neighbour; boundary faces follow, grouped by patch, oriented outwards. Patch "wall"
// has type wall (noSlip, wall functions), every other patch type patch and a free-stream
// condition (freestreamVelocity / freestreamPressure, inletOutlet for k and omega). The
// dictionaries and fields are written only where absent. Throws std::runtime_error naming the
// file on a write error.
void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir,
                         const FlowSpec& flow = {});

// The same polyMesh files directly in `polymesh_dir` (created if missing), nothing else.
void write_openfoam_polymesh(const BlockGrid& grid, const std::string& polymesh_dir);

}  // namespace hexmesh

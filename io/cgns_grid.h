// CGNS writer (libcgns mid-level API): one structured zone per block, BCs and 1-to-1 interfaces.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Writes `grid` as a CGNS file: base "Base" (3D), one Structured zone per block (named after
// the block, or "blockN" if names are missing or repeat) with GridCoordinates
// CoordinateX/Y/Z in double precision (i fastest). Each block face with a patch name becomes
// a BC_t with a vertex PointRange (1-based, begin/end corners of the face) and FamilyName =
// the patch name; type BCWall for "wall", BCFarfield for "farfield", BCTypeUserDefined
// otherwise, and each patch is a Family_t with the same FamilyBC. Block faces without a
// patch that fully coincide (same 4 corner nodes) with a face of another block are written
// as GridConnectivity1to1 with PointRange, PointRangeDonor and Transform. Throws
// std::runtime_error with the CGNS library's message on failure.
void write_cgns_grid(const BlockGrid& grid, const std::string& path);

}  // namespace hexmesh

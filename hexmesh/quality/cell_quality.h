// Quality measures of one hexahedron: corner determinants and Verdict's scaled Jacobian, per
// cell over a mesh or a block grid.
#pragma once

#include <array>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Verdict's hex scaled Jacobian, exactly as VTK 9.1 ships it (v_hex_scaled_jacobian): the
// minimum over the centre frame (principal axes) and the 8 corner frames (hex_corner_tets
// order) of det[e1,e2,e3] / (|e1||e2||e3|), in [-1, 1]; 1 for a box. Verdict's quirk is kept:
// if any of the 27 frame vectors has squared length <= 1e-30, the result is +1e30.
double hex_scaled_jacobian(const std::array<Vec3, 8>& p);

// The 9 frames hex_scaled_jacobian takes the minimum of, each det[e1,e2,e3] / (|e1||e2||e3|):
// the centre frame, then the 8 corner frames; a frame with a degenerate vector is +1e30.
std::array<double, 9> hex_frame_jacobians(const std::array<Vec3, 8>& p);

// det[a-c, b-c, d-c] of each corner tet (c, a, b, d) of hex_corner_tets, floating point.
std::array<double, 8> corner_determinants(const std::array<Vec3, 8>& p);

// Per-cell scaled Jacobian, #cells (parallel, deterministic).
std::vector<double> scaled_jacobians(const HexMesh& mesh);

// The same for the cells of a block grid, in to_hex_mesh order (block by block, i fastest),
// without building the unstructured mesh.
std::vector<double> scaled_jacobians(const BlockGrid& grid);

// The cells of one block of `grid` into out[0 .. block.cells().count()), i fastest.
void scaled_jacobians(const BlockGrid& grid, const Block& block, double* out);

}  // namespace hexmesh

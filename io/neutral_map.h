// NASA's Neutral Map File (.nmf): the block sizes, boundary conditions and 1-to-1 block
// interfaces of a multi-block structured grid, beside its Plot3D file.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

// Faces are numbered as the format numbers them: 1 k = 1, 2 k = kmax, 3 i = 1, 4 i = imax,
// 5 j = 1, 6 j = jmax; on each, the first and second index directions are cyclic: (i, j) on
// faces 1-2, (j, k) on 3-4, (k, i) on 5-6. Ranges are 1-based and inclusive.
struct NmfFaceRange {
    int block = 0;  // 1-based
    int face = 0;   // 1..6 as above
    int s1 = 0, e1 = 0, s2 = 0, e2 = 0;
};

struct NmfBoundary {
    std::string type;  // e.g. WALL, FARFIELD
    NmfFaceRange range;
};

// Point (u, v) of `first` (u from s1 to e1, v from s2 to e2) is the point of `second` at
// first direction s1' + |u - s1| step, second direction s2' + |v - s2| step (each step +1 or
// -1 as e' >= s' or not), or with the two directions of `second` exchanged when swap.
struct NmfInterface {
    NmfFaceRange first, second;
    bool swap = false;
};

struct NeutralMap {
    std::vector<std::array<int, 3>> dims;  // per block: IDIM JDIM KDIM
    std::vector<NmfBoundary> boundaries;
    std::vector<NmfInterface> interfaces;
};

// The map of a block grid: one boundary entry per patched block face (type WALL for "wall",
// FARFIELD for "farfield", else the patch's name), one ONE_TO_ONE entry per interface between
// two block faces whose nodes coincide (found from the shared node ids), whole faces.
NeutralMap neutral_map(const BlockGrid& grid);

// Writes it as text: the block table, then one line per entry
// ("Type B1 F1 S1 E1 S2 E2 [B2 F2 S1 E1 S2 E2 Swap]"), '#' comments as headers.
void write_neutral_map(const NeutralMap& map, const std::string& path);

// Reads a neutral map file (comments after '#', types quoted or not). Throws InputError
// naming the file and line for anything malformed or out of range.
NeutralMap read_neutral_map(const std::string& path);

// The grid face (BlockFace order: imin imax jmin jmax kmin kmax) of a map face 1..6, and back.
int nmf_face_to_block_face(int face);
int block_face_to_nmf_face(int block_face);

// Node (i, j, k), 0-based, of point (u, v) (1-based, in the face's cyclic directions) of a
// map face of a block with node counts `dims`.
std::array<int, 3> nmf_face_node(const std::array<int, 3>& dims, int face, int u, int v);

}  // namespace hexmesh

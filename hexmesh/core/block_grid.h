// Multi-block structured grid: one shared node array, each block a (i,j,k) view on it.
#pragma once

#include <array>
#include <cassert>
#include <string>
#include <vector>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/types.h"
#include "hexmesh/core/vertex_kind.h"

namespace hexmesh {

// Extents of a structured index box. Node dims and cell dims are both Dims; a block
// keeps its node dims, cell dims are node dims minus one in each direction.
struct Dims {
    int ni = 0, nj = 0, nk = 0;

    // 0 when any extent is 0 or less (e.g. the cells of a block without nodes).
    Id count() const { return ni > 0 && nj > 0 && nk > 0 ? Id(ni) * nj * nk : 0; }
    // Flat index, i fastest, computed in 64 bits.
    Id flat(int i, int j, int k) const {
        assert(i >= 0 && i < ni && j >= 0 && j < nj && k >= 0 && k < nk);
        return i + Id(ni) * (j + Id(nj) * k);
    }
    int operator[](int axis) const { return axis == 0 ? ni : axis == 1 ? nj : nk; }
};

// Block faces in the order imin, imax, jmin, jmax, kmin, kmax.
enum BlockFace { imin, imax, jmin, jmax, kmin, kmax };

// Their names, for files and messages.
inline constexpr const char* block_face_names[6] = {"imin", "imax", "jmin", "jmax", "kmin", "kmax"};

// A structured block: node dims plus the global id of each of its nodes (flat, i fastest).
// Neighbouring blocks list the same global ids on their common interface.
struct Block {
    std::string name;
    Dims nodes;
    std::vector<Id> node_ids;  // nodes.count() global node ids
    // Boundary patch of each face (BlockFace order): "wall", "farfield", ...; empty for a
    // face that is an interface with another block.
    std::array<std::string, 6> face_patch;

    Dims cells() const { return {nodes.ni - 1, nodes.nj - 1, nodes.nk - 1}; }
    Id node(int i, int j, int k) const { return node_ids[nodes.flat(i, j, k)]; }
};

struct BlockGrid {
    std::vector<Vec3> points;       // the shared node array
    std::vector<VertexKind> kinds;  // constraint per node, sized like points
    std::vector<Block> blocks;

    Id num_cells() const;
};

// Whether the cell at = (i, j, k) of a block of `cells` cell dims touches block face `face`
// (BlockFace order).
inline bool on_block_face(const Dims& cells, const std::array<int, 3>& at, int face) {
    return at[face / 2] == (face % 2 ? cells[face / 2] - 1 : 0);
}

// Global node ids of the 8 corners of cell (i,j,k) of a block, in VTK_HEXAHEDRON order.
std::array<Id, 8> cell_nodes(const Block& block, int i, int j, int k);

// Calls f(i, j, k, nodes) for every cell of the block, i fastest, with the cell's 8 global
// node ids in VTK_HEXAHEDRON order.
template <class F>
void for_each_cell(const Block& block, F&& f) {
    const Dims c = block.cells();
    for (int k = 0; k < c.nk; ++k)
        for (int j = 0; j < c.nj; ++j)
            for (int i = 0; i < c.ni; ++i) f(i, j, k, cell_nodes(block, i, j, k));
}

// The 8 node ids (cell_nodes order) of every cell with at least one node v where !held[v],
// in to_hex_mesh order (block by block, i fastest); held is sized like grid.points. Parallel.
std::vector<std::array<Id, 8>> cells_not_held(const BlockGrid& grid, const std::vector<bool>& held);

// All cells of all blocks as one unstructured mesh sharing the grid's points (block by block,
// i fastest within a block).
HexMesh to_hex_mesh(const BlockGrid& grid);

}  // namespace hexmesh

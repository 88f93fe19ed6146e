// Face topology of a block grid for the unstructured exporters (OpenFOAM, Gmsh, Medit).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/reference_hex.h"

namespace hexmesh {

// Cells are numbered as to_hex_mesh numbers them: block by block, i fastest. Cell faces use
// hex_faces order (x=0, x=1, y=0, y=1, z=0, z=1), which is BlockFace order on the block.
// Only the block boundaries are stored; neighbours inside a block are computed.
struct GridFaces {
    std::vector<Id> first_cell;  // per block: global id of its first cell
    // Per block and block face: the cell across each cell face of that block face (i or j
    // fastest as in face_cell_index), or -1 if the face is on the boundary.
    std::vector<std::array<std::vector<Id>, 6>> across;
    // Boundary patches in order of first appearance over blocks and faces. A block face with
    // no patch name that matches no other block falls in the patch "unassigned".
    std::vector<std::string> patch_names;
    std::vector<std::array<int, 6>> face_patch_index;  // per block face: patch index or -1
    Id internal_faces = 0;
    Id boundary_faces = 0;
};

// Matches block-boundary faces across blocks by their node ids. Throws std::invalid_argument
// if one face is shared by more than two cells.
GridFaces make_grid_faces(const BlockGrid& grid);

// Boundary faces per patch, in GridFaces::patch_names order (what for_each_patch_face visits).
std::vector<Id> patch_face_counts(const BlockGrid& grid, const GridFaces& faces);

// Position of the cell face at cell (i,j,k) of block face `face` in GridFaces::across.
inline Id face_cell_index(const Dims& cells, int face, int i, int j, int k) {
    const int axis = face / 2;
    if (axis == 0) return j + Id(cells.nj) * k;
    if (axis == 1) return i + Id(cells.ni) * k;
    return i + Id(cells.ni) * j;
}

// The cell across local face `face` of cell (i,j,k) of block `b`, or -1 on the boundary.
inline Id cell_across(const GridFaces& faces, const BlockGrid& grid, int b, int i, int j, int k,
                      int face) {
    const Dims c = grid.blocks[b].cells();
    int ijk[3] = {i, j, k};
    const int axis = face / 2, step = face % 2 ? 1 : -1;
    ijk[axis] += step;
    if (ijk[axis] >= 0 && ijk[axis] < c[axis])
        return faces.first_cell[b] + c.flat(ijk[0], ijk[1], ijk[2]);
    return faces.across[b][face][face_cell_index(c, face, i, j, k)];
}

// Face nodes of local face `face` of a cell, ordered so the right-hand normal points out of it.
inline std::array<Id, 4> cell_face_nodes(const Block& block, int i, int j, int k, int face) {
    const auto n = cell_nodes(block, i, j, k);
    const auto& f = hex_faces[face];
    return {n[f[0]], n[f[1]], n[f[2]], n[f[3]]};
}

// Calls f(owner, neighbour, nodes) for every internal face in upper-triangular order
// (ascending owner, then neighbour; owner < neighbour), nodes oriented owner -> neighbour.
template <class F>
void for_each_internal_face(const BlockGrid& grid, const GridFaces& faces, F&& f) {
    for (int b = 0; b < int(grid.blocks.size()); ++b) {
        const Block& block = grid.blocks[b];
        const Dims c = block.cells();
        for (int k = 0; k < c.nk; ++k)
            for (int j = 0; j < c.nj; ++j)
                for (int i = 0; i < c.ni; ++i) {
                    const Id self = faces.first_cell[b] + c.flat(i, j, k);
                    std::array<std::pair<Id, int>, 6> up;
                    int n = 0;
                    for (int face = 0; face < 6; ++face) {
                        const Id other = cell_across(faces, grid, b, i, j, k, face);
                        if (other > self) up[n++] = {other, face};
                    }
                    for (int m = 1; m < n; ++m)  // insertion sort of at most 6 entries
                        for (int q = m; q > 0 && up[q].first < up[q - 1].first; --q)
                            std::swap(up[q], up[q - 1]);
                    for (int m = 0; m < n; ++m)
                        f(self, up[m].first, cell_face_nodes(block, i, j, k, up[m].second));
                }
    }
}

// Calls f(b, face, i, j, k, owner, nodes) for every boundary face of patch `patch`: the face
// `face` of cell (i, j, k) of block b, its cell's global id and its nodes oriented outwards.
template <class F>
void for_each_patch_face_at(const BlockGrid& grid, const GridFaces& faces, int patch, F&& f) {
    for (int b = 0; b < int(grid.blocks.size()); ++b) {
        const Block& block = grid.blocks[b];
        const Dims c = block.cells();
        for (int face = 0; face < 6; ++face) {
            if (faces.face_patch_index[b][face] != patch) continue;
            const int axis = face / 2;
            int lo[3] = {0, 0, 0}, hi[3] = {c.ni, c.nj, c.nk};
            lo[axis] = face % 2 ? c[axis] - 1 : 0;
            hi[axis] = lo[axis] + 1;
            const std::vector<Id>& across = faces.across[b][face];
            for (int k = lo[2]; k < hi[2]; ++k)
                for (int j = lo[1]; j < hi[1]; ++j)
                    for (int i = lo[0]; i < hi[0]; ++i)
                        if (across[face_cell_index(c, face, i, j, k)] < 0)
                            f(b, face, i, j, k, faces.first_cell[b] + c.flat(i, j, k),
                              cell_face_nodes(block, i, j, k, face));
        }
    }
}

// Calls f(owner, nodes) for every boundary face of patch `patch`, nodes oriented outwards.
template <class F>
void for_each_patch_face(const BlockGrid& grid, const GridFaces& faces, int patch, F&& f) {
    for_each_patch_face_at(grid, faces, patch,
                           [&](int, int, int, int, int, Id owner, const std::array<Id, 4>& nodes) {
                               f(owner, nodes);
                           });
}

}  // namespace hexmesh

// VTK file formats, written and read with VTK's own classes.
#pragma once

#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Writes `grid` with VTK's XML writers: a .vtm multiblock file (one vtkStructuredGrid piece
// per block, named after the block, pieces in a folder beside it) or, for a single block, a
// .vts file; `path` must end in the matching extension. Each piece carries the cell array
// "scaled_jacobian", the point array "vertex_kind" (0 interior, 1 slip, 2 feature edge,
// 3 corner, 4 fixed) and the field data "block_name" (1 string) and "face_patch" (6 strings,
// imin imax jmin jmax kmin kmax; "" for a block interface). Throws std::runtime_error naming
// the file if VTK cannot write it.
void write_vtk_grid(const BlockGrid& grid, const std::string& path);

// write_vtk_grid one block at a time, for a grid made block by block and never held whole:
// add() writes each block's piece as it comes (the grid passed holds that block's points),
// finish() the .vtm index that names them. The files are those write_vtk_grid writes.
class VtkGridWriter {
  public:
    // `path`: .vts when num_blocks is 1, else .vtm (std::runtime_error otherwise); the
    // folder of a .vtm's pieces is created here.
    VtkGridWriter(std::string path, size_t num_blocks);
    void add(const BlockGrid& grid, const Block& block);
    // Throws std::logic_error unless num_blocks blocks were added.
    void finish();

    // For a grid whose blocks several processes write, each its own: add_piece() writes
    // `block` as block `index` of the grid, write_index() (one process) the .vtm naming every
    // block (`names`, in order). The files are those of add() and finish().
    void add_piece(size_t index, const BlockGrid& grid, const Block& block) const;
    void write_index(const std::vector<std::string>& names) const;

  private:
    std::string path_;
    size_t num_blocks_;
    std::string pieces_;              // a .vtm's stem STEM: its pieces are STEM/STEM_<b>.vts
    std::vector<std::string> names_;  // of the blocks written so far
};

// Reads a .vts or .vtm written by write_vtk_grid back into a block grid: blocks (names from
// the .vtm or "block_name"), face patches, vertex kinds, and shared nodes, points that are
// exactly equal across (or within) pieces becoming one node. Pieces without the field data
// get empty patches. Throws InputError when the file is missing or not structured.
BlockGrid read_vtk_block_grid(const std::string& path);

// Reads the hexahedra of a .vts, .vtu, .vtk (legacy) or .vtm file into one mesh. Points that
// coincide exactly across the pieces of a .vtm are merged, so block interfaces become
// internal faces. Voxels are reordered to VTK_HEXAHEDRON order. Also reads the exporters'
// other formats by extension: Gmsh .msh, Medit .mesh, Plot3D .xyz .x .p3d .g. Throws
// InputError when the file is missing, unreadable, or holds cells that are not hexahedra.
HexMesh read_vtk_mesh(const std::string& path);

}  // namespace hexmesh

// Plot3D multi-block whole grids (3D, no iblank): Fortran-unformatted, C binary and ASCII.
#pragma once

#include <string>

#include "hexmesh/core/block_grid.h"

namespace hexmesh {

enum class Plot3dEncoding { fortran, c_binary, ascii };

struct Plot3dFormat {
    Plot3dEncoding encoding = Plot3dEncoding::fortran;
    bool single_precision = false;  // 4-byte floats instead of 8-byte doubles
};

// Layout (little-endian binary, 4-byte integers): nblocks; ni nj nk of every block; then per
// block all x (i fastest, then j, then k), all y, all z. Fortran-unformatted wraps each of
// these three kinds of record (nblocks / all dims / one block's x y z) in 4-byte byte-count
// markers; C binary has no markers; ASCII writes the same numbers as text, doubles with the
// shortest representation that reads back bitwise.
//
// Boundary patches go to the side file PATH.patches.json, which read_plot3d uses if present:
//   {"format": "hexmesh-plot3d-patches", "version": 1,
//    "blocks": [{"name": "core", "dims": [ni, nj, nk],
//                "face_patch": ["", "", "", "", "", "wall"]}, ...]}
// one entry per block in file order; face_patch in the order imin imax jmin jmax kmin kmax,
// "" for a face shared with another block. The same patches, and the 1-to-1 interfaces between
// blocks, go to NASA's Neutral Map File beside it, PATH with extension .nmf
// (io/neutral_map.h), which other Plot3D tools and solvers read. Throws std::runtime_error on a
// write error.
void write_plot3d(const BlockGrid& grid, const std::string& path, const Plot3dFormat& format);

// Path of the patch side file of a Plot3D grid file.
std::string plot3d_patch_file(const std::string& path);

// Path of the neutral map file of a Plot3D grid file: PATH with extension .nmf.
std::string plot3d_map_file(const std::string& path);

// Reads any of the variants above (encoding and precision detected from the file), merging
// points that are exactly equal across blocks into shared nodes; patches from PATH.patches.json,
// else from the neutral map file (boundary types WALL and FARFIELD as "wall" and "farfield").
// Throws InputError when the file is missing, truncated or not a Plot3D whole grid.
BlockGrid read_plot3d(const std::string& path);

// The variant read_plot3d detects for `path`.
Plot3dFormat detect_plot3d_format(const std::string& path);

}  // namespace hexmesh

// Reading triangulated surfaces: STL (ASCII and binary), OBJ, OFF, PLY (ASCII, binary LE).
#pragma once

#include <string>

#include "hexmesh/core/triangle_surface.h"
#include "io/input_error.h"

namespace hexmesh {

struct SurfaceReadOptions {
    // Keep zero-area triangles (repeated or collinear points, area <= 1e-12 of the longest
    // edge squared) instead of refusing the file; `hexmesh inspect` counts them.
    bool allow_degenerate = false;
};

// Reads the surface in `path`; the format comes from the extension (.stl .obj .off .ply,
// any case); STL is ASCII or binary whatever its first word. Polygons are split into
// triangle fans; STL corners with identical coordinates become one point. Units are kept.
// Throws InputError naming the file (and the line of an ASCII file, or the triangle of a
// binary one) for: a missing or empty file, an unknown extension, a truncated or malformed
// file, a non-finite coordinate, an index out of range, a zero-area triangle (unless
// allowed), and a file with no triangle (e.g. a point cloud).
TriangleSurface read_surface(const std::string& path, const SurfaceReadOptions& options = {});

}  // namespace hexmesh

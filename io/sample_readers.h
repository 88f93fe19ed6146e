// Reading bodies given by samples: oriented point clouds (PLY, XYZ) and cross-section stacks.
#pragma once

#include <string>

#include "hexmesh/core/point_samples.h"

namespace hexmesh {

// Reads points with normals; the format comes from the extension (any case):
// - .ply: ASCII or binary little-endian; element "vertex" with properties x y z nx ny nz
//   (any numeric types, any order, other properties and elements skipped; faces ignored).
// - .xyz: text, one point per line "x y z nx ny nz"; blank lines and '#' comments skipped.
// Normals must point out of the body; they are kept as read (PointCloudSdf normalizes).
// Units are kept. Throws InputError naming the file and the line (text) or vertex (binary)
// for: a missing or empty file, an unknown extension, missing normals (no nx ny nz, or a
// line with fewer than 6 numbers), a non-finite number, a zero normal, no point at all.
OrientedPoints read_point_cloud(const std::string& path);

// Reads a stack of cross-sections (perpendicular to z) from a text file (.txt or any
// extension):
//
//   # a cylinder of radius 1 from z = 0 to 2     ('#' starts a comment; blank lines skipped)
//   slice 0.0        # starts a section at z = 0 and its first closed polyline
//   1 0              # x y: the points of the polyline, in order, each once
//   0 1
//   -1 0
//   0 -1
//   loop             # starts another closed polyline of the same section (an island or
//   ...              #   a hole: inside is decided by the even-odd rule)
//   slice 2.0
//   ...
//
// A closing point equal to the first is dropped. Sections may come in any z order; they
// are sorted. Units are kept. Throws InputError naming the file and line for: a missing
// file, a point before any `slice`, a line that is not `slice Z`, `loop` or `x y`, a
// non-finite number, a polyline with fewer than 3 points, two sections at the same z, and
// fewer than 2 sections.
SectionStack read_sections(const std::string& path);

// What a geometry file holds, by its extension (any case) and, for .ply, its header: a
// triangle surface (.stl .obj .off, .ply with faces or without normals), an oriented point
// cloud (.xyz, .ply with vertex normals and no faces) or a cross-section stack (any other
// extension). Throws InputError for a .ply that cannot be opened or has a bad header.
enum class GeometryFileKind { surface, points, sections };
GeometryFileKind geometry_file_kind(const std::string& path);

}  // namespace hexmesh

// Turns the geometry of a case file into an implicit body.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "hexmesh/core/triangle_surface.h"
#include "io/case_file.h"
#include "surface/body.h"

namespace hexmesh {

// The surface in `file` (io/surface_reader.h) without its zero-area triangles (repeated or
// collinear points, as marching cubes and some CAD exports leave them: removed by
// without_zero_area_triangles, surface/surface_diagnostics.h); when there were some, `note`
// (if given) says how many, for the log. A file whose zero-area triangles cannot be removed so
// is refused by the reader's own message (the first one's line, or triangle in a binary STL,
// and corners), saying why.
TriangleSurface read_surface_file(const std::string& file, std::string* note = nullptr);

// The implicit function of `spec`: primitives, CSG nodes and their transforms; a surface file
// is read by read_surface_file.
Body make_body(const GeometrySpec& spec);

// The triangle surface of a geometry that is one surface file (moved by its transform, its
// zero-area triangles removed as for make_body, how many logged to `log`), the reference of
// the fidelity report and of the sphere map, its triangles facing outwards (turned over when
// they all faced inwards); nullopt for formulas and CSG.
std::optional<TriangleSurface> reference_surface(const GeometrySpec& spec,
                                                 std::ostream* log = nullptr);

}  // namespace hexmesh

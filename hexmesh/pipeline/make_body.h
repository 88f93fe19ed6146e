// Turns the geometry of a case file into an implicit body.
#pragma once

#include <optional>

#include "hexmesh/core/triangle_surface.h"
#include "io/case_file.h"
#include "surface/body.h"

namespace hexmesh {

// The implicit function of `spec`: primitives, CSG nodes and their transforms.
Body make_body(const GeometrySpec& spec);

// The triangle surface of a geometry that is one surface file (moved by its transform), the
// reference of the fidelity report and of the sphere map, its triangles facing outwards
// (turned over when they all faced inwards); nullopt for formulas and CSG.
std::optional<TriangleSurface> reference_surface(const GeometrySpec& spec);

}  // namespace hexmesh

// Turns the geometry of a case file into an implicit body.
#pragma once

#include "io/case_file.h"
#include "surface/body.h"

namespace hexmesh {

// The implicit function of `spec`: primitives, CSG nodes and their transforms.
Body make_body(const GeometrySpec& spec);

}  // namespace hexmesh

// The surface u = 0 of a formula or CSG body as a closed triangle surface: what the sphere map
// (hexmesh/pipeline/sphere_map.h) takes for a body that is not star-shaped.
#pragma once

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

// u = 0 of `body` contoured (VTK's flying edges) from its values at the nodes of a lattice of
// `cells` cells along the longest side of the body's bounds, padded by two cells all round;
// zero-area triangles (a node exactly on u = 0) removed (surface/surface_diagnostics.h), the
// triangles facing outwards. Parts thinner than a lattice cell may be lost or cut off, parts
// nearer than one joined; the surface is only a guide for placing wall nodes, which are then
// projected onto u = 0 of the body itself. Throws std::invalid_argument when no closed
// manifold surface comes out (no point inside, or zero-area triangles CGAL cannot mend).
TriangleSurface contour_body(const ImplicitFunction& body, int cells);

}  // namespace hexmesh

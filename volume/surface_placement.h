// Placing boundary nodes on u = 0 by radial projection from an interior centre.
#pragma once

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

// The first point of u = 0 on the ray centre + t * direction (t > 0), polished by the
// projection operator V to |u| < 1e-12 * length_scale. `centre` must be inside the body.
// Throws std::invalid_argument when the ray leaves the body's bounds without crossing
// u = 0 (the body is not star-shaped around `centre`).
Vec3 place_on_surface(const ImplicitFunction& body, const Vec3& centre, const Vec3& direction,
                      double length_scale);

// Throws std::invalid_argument unless u(centre) < 0.
void require_inside(const ImplicitFunction& body, const Vec3& centre);

}  // namespace hexmesh

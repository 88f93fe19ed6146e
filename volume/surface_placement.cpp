#include "volume/surface_placement.h"

#include <fmt/format.h>

#include <stdexcept>

#include "surface/projection.h"

namespace hexmesh {

void require_inside(const ImplicitFunction& body, const Vec3& centre) {
    const double u = body.value(centre);
    if (!(u < 0)) {
        throw std::invalid_argument(fmt::format(
            "the grid centre ({:.6g}, {:.6g}, {:.6g}) is not inside the body (u = {:.6g}); "
            "give a centre inside it",
            centre.x(), centre.y(), centre.z(), u));
    }
}

Vec3 place_on_surface(const ImplicitFunction& body, const Vec3& centre, const Vec3& direction,
                      double length_scale) {
    const auto hit = intersect_ray(body, centre, direction.normalized(), length_scale);
    if (!hit) {
        throw std::invalid_argument(fmt::format(
            "the ray from the centre in direction ({:.4g}, {:.4g}, {:.4g}) does not cross the "
            "body surface: the body must be star-shaped around the grid centre",
            direction.x(), direction.y(), direction.z()));
    }
    ProjectionOptions options;
    options.tolerance = 1e-12;
    return project_to_surface(body, *hit, length_scale, options).point;
}

}  // namespace hexmesh

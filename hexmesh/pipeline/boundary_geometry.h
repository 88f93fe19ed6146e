// What boundary vertices slide on (docs/architecture.md#boundary-conditions): the surface u = 0 of
// an implicit body, with creases and corners from its active pieces, or a triangle surface, with
// creases by dihedral angle. One interface for the untangler's constraints, the vertex kinds and
// the distances a report measures.
#pragma once

#include <functional>
#include <memory>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/core/vertex_kind.h"
#include "surface/sharp_features.h"
#include "untangle/problem.h"

namespace hexmesh {

class BoundaryGeometry {
  public:
    // u = 0 of `body` (kept alive by the shared pointer); tolerances relative to length_scale.
    static BoundaryGeometry implicit(std::shared_ptr<const ImplicitFunction> body,
                                     double length_scale);
    // The triangles of `surface`, with the creases detect_sharp_features finds by `creases`.
    static BoundaryGeometry triangles(const TriangleSurface& surface, const FeatureOptions& creases,
                                      double length_scale);

    // The constraint of a boundary vertex at x: slip, feature_edge within `reach` of a crease,
    // corner within `reach` of a corner.
    VertexKind kind_at(const Vec3& x, double reach) const { return kind_at_(x, reach); }
    // x moved onto the part the kind names: the surface, its nearby crease or corner; other
    // kinds unchanged.
    Vec3 place(const Vec3& x, VertexKind kind) const;
    // The surface's normal near x (any length) and the nearest crease's direction at x.
    Vec3 surface_normal(const Vec3& x) const { return normal_(x); }
    Vec3 crease_direction(const Vec3& x) const { return tangent_(x); }
    double surface_distance(const Vec3& x) const { return (to_surface_(x) - x).norm(); }
    double crease_distance(const Vec3& x) const { return (to_crease_(x) - x).norm(); }
    // The four geometry callbacks of the untangler.
    void constrain(untangle::Problem& problem) const;

  private:
    std::function<VertexKind(const Vec3&, double)> kind_at_;
    std::function<Vec3(const Vec3&)> normal_, to_surface_, tangent_, to_crease_, to_corner_;
};

}  // namespace hexmesh

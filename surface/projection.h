// Projection onto the surface u = 0 (operator V, docs/architecture.md#boundary-conditions), tangent
// frames, ray hits.
#pragma once

#include <optional>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

struct ProjectionOptions {
    double tolerance = 1e-10;  // stop when |u| < tolerance * length_scale
    int max_iterations = 100;  // V steps, not counting bisection steps
    double relaxation = 1.0;   // tau1 in p <- p - tau1 u grad u / |grad u|^2
};

struct Projection {
    Vec3 point;       // the projected point (never NaN: the start point if all fails)
    double residual;  // |u(point)|, +inf if u is not finite at the start point
    int iterations;   // projection steps plus bisection steps taken
    bool converged;   // residual < tolerance * length_scale
};

// Moves p onto u = 0 by the steps p <- p - tau1 u grad u / |grad u|^2 (at most 4 |u| long).
// Safeguards, in order, when a step does not cut |u| by about half the expected amount:
// a step that jumped over the surface is refined by bisection on its segment; else a step
// onto the crease of the two pieces seen (CSG) or one more plain step is tried; else the
// surface is sought along the step's line (sphere tracing, then bisection; after three
// stalls along the line to the bounds' centre); else the step is halved until |u|
// decreases; else the line is searched backwards. A vanishing gradient reuses the previous
// direction. relaxation should lie in (0, 2); length_scale (> 0, typically the cell size h)
// sets the tolerance.
Projection project_to_surface(const ImplicitFunction& u, const Vec3& p, double length_scale,
                              const ProjectionOptions& options = {});

// Orthonormal, right-handed (t1 x t2 = normal); normal = grad u / |grad u| (+z if the
// gradient vanishes). t1, t2 span the tangent plane of the level set through p.
struct TangentFrame {
    Vec3 normal, t1, t2;
};
TangentFrame tangent_frame(const ImplicitFunction& u, const Vec3& p);

// First point where the ray origin + t direction (t >= 0) crosses u = 0, to
// |u| < 1e-12 length_scale. Marches by sphere tracing (steps of 0.9 |u|, at least
// 1e-3 length_scale, so features thinner than that may be stepped over) until the ray
// leaves u.bounds(). Meant for an origin inside (u < 0) but works from outside too.
// nullopt if no crossing; throws std::invalid_argument for a zero direction.
std::optional<Vec3> intersect_ray(const ImplicitFunction& u, const Vec3& origin,
                                  const Vec3& direction, double length_scale);

}  // namespace hexmesh

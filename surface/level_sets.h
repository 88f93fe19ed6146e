// Level sets of a body's functions as surfaces: where a grid centre sees the whole body, and
// whether a level is star-shaped around it.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

// The deepest point of the body (inside, u < 0, and farthest from its surface: `depth`, or -u
// when no depth is given) on the lattice of spacing `step` over its bounds, then moved to the
// best of its neighbours at half, quarter ... the step: where a grid centre sees the most of
// the body. A surface file's u is a distance only near the surface: its depth must come from
// elsewhere (surface/exact_distance.h). nullopt when no lattice point is inside.
std::optional<Vec3> deepest_point(const ImplicitFunction& body, double step,
                                  const std::function<double(const Vec3&)>& depth = {});

// Points about as deep as the deepest (on the lattice of deepest_point, within half its step of
// the greatest depth: a plateau, as along bars of one thickness), at most `count`, each at least
// that depth from those before it, the ones whose ball of twice the depth holds the most of the
// body first: where bars meet before along one. Empty when no lattice point is inside.
std::vector<Vec3> deepest_candidates(const ImplicitFunction& body, double step, int count,
                                     const std::function<double(const Vec3&)>& depth = {});

// Unit directions spread evenly over the sphere (Fibonacci lattice), `count` of them.
std::vector<Vec3> sphere_directions(int count);

// Whether the level F = c of `f` is star-shaped around `centre`, seen along `directions`: each
// ray centre + t dir crosses it once (F - c sampled every `step` out to `reach`, the sign
// changes once, from below to above), and there at an angle of at most max_angle_deg between
// the ray and grad F. With `crossings`, when it is: the point where each ray crosses it.
bool star_shaped_level(const ImplicitFunction& f, double c, const Vec3& centre,
                       const std::vector<Vec3>& directions, double step, double reach,
                       double max_angle_deg, std::vector<Vec3>* crossings = nullptr);

}  // namespace hexmesh

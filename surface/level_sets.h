// Level sets of a body's functions as surfaces: where a grid centre sees the whole body, and
// whether a level is star-shaped around it.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

// The depths of the body on the lattice of spacing `step` over its bounds (node c at
// bounds.lo + step c, x fastest): inside (u < 0) `depth` there, or -u when no depth is given;
// -infinity outside. A surface file's u is a distance only near the surface: its depth must
// come from elsewhere (surface/exact_distance.h).
struct DepthLattice {
    Vec3 lo = Vec3::Zero();
    double step = 0;
    Eigen::Vector3i n = Eigen::Vector3i::Zero();  // nodes along x, y, z
    std::vector<double> depths;

    Vec3 at(const Eigen::Vector3i& c) const { return lo + step * c.cast<double>(); }
    size_t index(const Eigen::Vector3i& c) const {
        return (size_t(c.z()) * n.y() + c.y()) * n.x() + c.x();
    }
};
DepthLattice depth_lattice(const ImplicitFunction& body, double step,
                           const std::function<double(const Vec3&)>& depth = {});

// The deepest node of `lattice` (depth_lattice of `body` with the same `depth`; of equals, the
// least in x, then y, then z), then moved to the best of its neighbours at half, quarter ...
// the step: where a grid centre sees the most of the body. nullopt when no node is inside.
std::optional<Vec3> deepest_point(const ImplicitFunction& body, const DepthLattice& lattice,
                                  const std::function<double(const Vec3&)>& depth = {});

// Nodes of `lattice` about as deep as the deepest (within half its step of the greatest depth:
// a plateau, as along bars of one thickness), at most `count`, each at least that depth from
// those before it, the ones whose ball of twice the depth holds the most of the body first:
// where bars meet before along one. Empty when no node is inside.
std::vector<Vec3> deepest_candidates(const DepthLattice& lattice, int count);

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

// A triangulated surface as read from a file: shared points and triangles of point ids.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

// points: #P positions in geometry units; triangles: #T triples of ids into points,
// counter-clockwise seen from outside when the file is consistently oriented. Nothing else
// is promised: the surface may be open, non-manifold or self-intersecting (a "soup").
struct TriangleSurface {
    std::vector<Vec3> points;
    std::vector<std::array<int, 3>> triangles;
};

// One key per undirected edge between point ids a and b (either order): for maps and sorts
// of a surface's edges.
inline std::uint64_t edge_key(int a, int b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::uint32_t(std::max(a, b));
}

// How many triangles use each undirected edge (edge_key): 1 on a boundary, 2 inside a closed
// manifold surface, more where it is not manifold.
inline std::unordered_map<std::uint64_t, int> edge_uses(
    const std::vector<std::array<int, 3>>& triangles) {
    std::unordered_map<std::uint64_t, int> uses;
    uses.reserve(2 * triangles.size());
    for (const auto& t : triangles)
        for (int e = 0; e < 3; ++e) ++uses[edge_key(t[e], t[(e + 1) % 3])];
    return uses;
}

// Axis-aligned bounds of the points (lo = hi = 0 for an empty surface).
inline Box3 surface_bounds(const TriangleSurface& s) {
    return bounds_of(s.points);
}

// The total area of the triangles.
inline double surface_area(const TriangleSurface& s) {
    double area = 0;
    for (const auto& t : s.triangles)
        area +=
            0.5 * (s.points[t[1]] - s.points[t[0]]).cross(s.points[t[2]] - s.points[t[0]]).norm();
    return area;
}

// The volume the triangles enclose, signed: > 0 when they face outwards (counter-clockwise
// seen from outside), < 0 when every one faces inwards (the sum of the tetrahedra from `apex`
// to each triangle; exact for a closed surface, whatever the apex, and rounded least with an
// apex near the surface, e.g. the centre of its bounds for a body far from the origin).
inline double signed_volume(const TriangleSurface& s, const Vec3& apex = Vec3::Zero()) {
    double six_v = 0;
    for (const auto& t : s.triangles)
        six_v += (s.points[t[0]] - apex).dot((s.points[t[1]] - apex).cross(s.points[t[2]] - apex));
    return six_v / 6;
}

// Turns every triangle over (reverses its point order).
inline void turn_over(TriangleSurface& s) {
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
}

}  // namespace hexmesh

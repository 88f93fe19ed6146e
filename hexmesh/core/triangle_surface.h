// A triangulated surface as read from a file: shared points and triangles of point ids.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
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

// Axis-aligned bounds of the points (lo = hi = 0 for an empty surface).
inline Box3 surface_bounds(const TriangleSurface& s) {
    Box3 box;
    if (s.points.empty()) return box;
    box.lo = box.hi = s.points[0];
    for (const Vec3& p : s.points) {
        box.lo = box.lo.cwiseMin(p);
        box.hi = box.hi.cwiseMax(p);
    }
    return box;
}

}  // namespace hexmesh

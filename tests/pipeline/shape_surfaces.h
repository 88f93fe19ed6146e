// Closed triangle surfaces of bodies that are not star-shaped, built in tests.
#pragma once

#include <map>
#include <utility>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh::test {

// Every triangle split in four at its edges' midpoints, `times` times over.
inline TriangleSurface subdivided(TriangleSurface s, int times) {
    for (int round = 0; round < times; ++round) {
        std::map<std::pair<int, int>, int> mid;
        const auto midpoint = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto [it, added] = mid.try_emplace(key, int(s.points.size()));
            if (added) s.points.push_back(0.5 * (s.points[a] + s.points[b]));
            return it->second;
        };
        std::vector<std::array<int, 3>> next;
        for (const auto& t : s.triangles) {
            const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                      ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({ab, t[1], bc});
            next.push_back({ca, bc, t[2]});
            next.push_back({ab, bc, ca});
        }
        s.triangles = std::move(next);
    }
    return s;
}

// A U, 1 wide and tall, 0.2 thick (z in [-0.1, 0.1]): arms 0.2 wide around a gap 0.6 wide and
// 0.8 deep, open towards +y. Counter-clockwise from outside, subdivided `times` times.
inline TriangleSurface u_surface(int times = 2) {
    const double outline[8][2] = {{-0.5, -0.5}, {0.5, -0.5},  {0.5, 0.5},  {0.3, 0.5},
                                  {0.3, -0.3},  {-0.3, -0.3}, {-0.3, 0.5}, {-0.5, 0.5}};
    const int cap[6][3] = {{0, 1, 4}, {0, 4, 5}, {4, 1, 2}, {4, 2, 3}, {0, 5, 6}, {0, 6, 7}};
    TriangleSurface s;
    for (double z : {-0.1, 0.1})
        for (const auto& p : outline) s.points.emplace_back(p[0], p[1], z);
    for (const auto& t : cap) {
        s.triangles.push_back({t[0], t[2], t[1]});              // bottom, seen from -z
        s.triangles.push_back({8 + t[0], 8 + t[1], 8 + t[2]});  // top
    }
    for (int a = 0; a < 8; ++a) {
        const int b = (a + 1) % 8;
        s.triangles.push_back({a, b, 8 + b});
        s.triangles.push_back({a, 8 + b, 8 + a});
    }
    return subdivided(s, times);
}

}  // namespace hexmesh::test

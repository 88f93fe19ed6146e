// Star-shaped test bodies written as binary STL files: a radius function of the direction
// sampled on a subdivided octahedron.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh::test_support {

// Writes the closed surface r(d) d (d over unit directions) as a binary STL of 8 level^2
// triangles, counter-clockwise seen from outside.
inline void write_star_stl(const std::string& path,
                           const std::function<double(const Vec3&)>& radius, int level) {
    auto at = [&](const Vec3& v) {
        const Vec3 d = v.normalized();
        return Vec3(radius(d) * d);
    };
    std::vector<std::array<Vec3, 3>> triangles;
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) {
                const Vec3 a(sx, 0, 0), b(0, sy, 0), c(0, 0, sz);
                auto lattice = [&](int i, int j) {
                    return Vec3((i * a + j * b + (level - i - j) * c) / level);
                };
                const bool flip = sx * sy * sz < 0;
                auto add = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
                    if (flip)
                        triangles.push_back({at(p), at(r), at(q)});
                    else
                        triangles.push_back({at(p), at(q), at(r)});
                };
                for (int i = 0; i < level; ++i)
                    for (int j = 0; j < level - i; ++j) {
                        add(lattice(i, j), lattice(i + 1, j), lattice(i, j + 1));
                        if (i + j + 1 < level)
                            add(lattice(i + 1, j), lattice(i + 1, j + 1), lattice(i, j + 1));
                    }
            }
    std::ofstream out(path, std::ios::binary);
    const std::string header(80, ' ');
    out.write(header.data(), 80);
    const std::uint32_t count = std::uint32_t(triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : triangles) {
        const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
        float values[12];
        for (int c = 0; c < 3; ++c) values[c] = float(n[c]);
        for (int v = 0; v < 3; ++v)
            for (int c = 0; c < 3; ++c) values[3 + 3 * v + c] = float(t[v][c]);
        out.write(reinterpret_cast<const char*>(values), sizeof values);
        out.write("\0\0", 2);
    }
}

// A peanut along x: an ellipsoid 1.4 x 0.7 x 0.7 pinched by 30 % at its waist (x = 0), so
// its surface is concave across the waist while every ray from the origin crosses it once.
inline double peanut_radius(const Vec3& d) {
    const double ellipsoid = 1 / std::sqrt(std::pow(d.x() / 1.4, 2) + std::pow(d.y() / 0.7, 2) +
                                           std::pow(d.z() / 0.7, 2));
    return ellipsoid * (1 - 0.3 * std::exp(-d.x() * d.x() / 0.08));
}

}  // namespace hexmesh::test_support

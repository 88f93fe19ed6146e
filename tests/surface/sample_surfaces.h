// Triangle surfaces generated in tests (sphere, box, cylinder) and STL writers for them.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh::test {

// Latitude-longitude sphere, counter-clockwise from outside: 2 poles + (lat-1)*lon points.
inline TriangleSurface uv_sphere(const Vec3& center, double radius, int lon, int lat) {
    const double pi = 3.14159265358979323846;
    TriangleSurface s;
    s.points.push_back(center + radius * Vec3::UnitZ());
    for (int k = 1; k < lat; ++k)
        for (int j = 0; j < lon; ++j) {
            const double theta = pi * k / lat, phi = 2 * pi * j / lon;
            s.points.push_back(center + radius * Vec3(std::sin(theta) * std::cos(phi),
                                                      std::sin(theta) * std::sin(phi),
                                                      std::cos(theta)));
        }
    s.points.push_back(center - radius * Vec3::UnitZ());
    const int south = static_cast<int>(s.points.size()) - 1;
    auto ring = [&](int k, int j) { return 1 + (k - 1) * lon + (j % lon); };
    for (int j = 0; j < lon; ++j) {
        s.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
        for (int k = 1; k + 1 < lat; ++k) {
            const int a = ring(k, j), b = ring(k, j + 1), c = ring(k + 1, j + 1),
                      d = ring(k + 1, j);
            s.triangles.push_back({a, d, c});
            s.triangles.push_back({a, c, b});
        }
        s.triangles.push_back({south, ring(lat - 1, j + 1), ring(lat - 1, j)});
    }
    return s;
}

// `s` without its triangles whose centroid lies above the plane z = `z`: a surface with a
// hole there (its points stay, unused).
inline TriangleSurface without_cap(TriangleSurface s, double z) {
    std::vector<std::array<int, 3>> kept;
    for (const auto& t : s.triangles)
        if ((s.points[t[0]].z() + s.points[t[1]].z() + s.points[t[2]].z()) / 3 <= z)
            kept.push_back(t);
    s.triangles = std::move(kept);
    return s;
}

// A scan-like surface: uv_sphere(0, 1, 24, 12) with each point moved along its radius by up
// to 8 % (fixed seed), so that its edges turn by every angle from 0 to beyond 30 degrees.
inline TriangleSurface bumpy_sphere() {
    TriangleSurface s = uv_sphere(Vec3::Zero(), 1, 24, 12);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> bump(0.92, 1.08);
    for (Vec3& p : s.points) p *= bump(random);
    return s;
}

// Box [lo, hi], each face split into n x n squares of 2 triangles, outward orientation.
inline TriangleSurface box_surface(const Vec3& lo, const Vec3& hi, int n = 1) {
    TriangleSurface s;
    std::map<std::array<double, 3>, int> ids;
    auto id = [&](const Vec3& p) {
        const auto [it, inserted] = ids.try_emplace({p.x(), p.y(), p.z()}, (int)s.points.size());
        if (inserted) s.points.push_back(p);
        return it->second;
    };
    auto coord = [&](int axis, int i) { return lo[axis] + (hi[axis] - lo[axis]) * i / n; };
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const int u = (a + 1) % 3, v = (a + 2) % 3;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    int q[4];
                    const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
                    for (int c = 0; c < 4; ++c) {
                        Vec3 p;
                        p[a] = side ? hi[a] : lo[a];
                        p[u] = coord(u, i + di[c]);
                        p[v] = coord(v, j + dj[c]);
                        q[c] = id(p);
                    }
                    if (side) {
                        s.triangles.push_back({q[0], q[1], q[2]});
                        s.triangles.push_back({q[0], q[2], q[3]});
                    } else {
                        s.triangles.push_back({q[0], q[2], q[1]});
                        s.triangles.push_back({q[0], q[3], q[2]});
                    }
                }
        }
    return s;
}

// `s` (closed, at least 8 triangles) with two zero-area triangles, as marching cubes and some
// CAD exports leave them: the edge (a, c) of triangle 7 = (a, c, d) split at its middle b on
// that triangle's side only, the gap against the unsplit neighbour (c, a, e) filled by the
// needle (a, c, b); and (d, d, a), a triangle with a repeated point. Still closed and oriented.
inline TriangleSurface with_zero_area_triangles(TriangleSurface s) {
    const int t = 7;
    const int a = s.triangles[t][0], c = s.triangles[t][1], d = s.triangles[t][2];
    s.points.push_back(0.5 * (s.points[a] + s.points[c]));
    const int b = int(s.points.size()) - 1;
    s.triangles[t] = {a, b, d};
    s.triangles.push_back({b, c, d});
    s.triangles.push_back({a, c, b});  // the needle
    s.triangles.push_back({d, d, a});  // a repeated point
    return s;
}

// Capped cylinder about the z axis through the origin, caps as fans from their centres.
inline TriangleSurface cylinder_surface(double radius, double height, int segments) {
    const double pi = 3.14159265358979323846;
    TriangleSurface s;
    for (int level = 0; level < 2; ++level)
        for (int j = 0; j < segments; ++j) {
            const double phi = 2 * pi * j / segments;
            s.points.emplace_back(radius * std::cos(phi), radius * std::sin(phi),
                                  (level - 0.5) * height);
        }
    const int bottom = 2 * segments, top = bottom + 1;
    s.points.emplace_back(0, 0, -0.5 * height);
    s.points.emplace_back(0, 0, 0.5 * height);
    for (int j = 0; j < segments; ++j) {
        const int b0 = j, b1 = (j + 1) % segments, t0 = segments + j, t1 = segments + b1;
        s.triangles.push_back({b0, b1, t1});
        s.triangles.push_back({b0, t1, t0});
        s.triangles.push_back({top, t0, t1});
        s.triangles.push_back({bottom, b1, b0});
    }
    return s;
}

// Torus about the z axis through the origin (genus 1): n x m quads split in two.
inline TriangleSurface torus_surface(double major, double minor, int n, int m) {
    const double pi = 3.14159265358979323846;
    TriangleSurface s;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            const double a = 2 * pi * i / n, b = 2 * pi * j / m;
            s.points.emplace_back((major + minor * std::cos(b)) * std::cos(a),
                                  (major + minor * std::cos(b)) * std::sin(a), minor * std::sin(b));
        }
    const auto id = [&](int i, int j) { return (i % n) * m + (j % m); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return s;
}

// Binary STL; the 80-byte header starts with "solid" on purpose (as many exporters do).
inline void write_stl_binary(const std::string& path, const TriangleSurface& s) {
    std::ofstream out(path, std::ios::binary);
    char header[80] = {};
    std::strncpy(header, "solid written by a hexmesh test", sizeof header);
    out.write(header, 80);
    const std::uint32_t n = static_cast<std::uint32_t>(s.triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : s.triangles) {
        float v[12] = {};
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a) v[3 + 3 * c + a] = static_cast<float>(s.points[t[c]][a]);
        out.write(reinterpret_cast<const char*>(v), sizeof v);
        const std::uint16_t attribute = 0;
        out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
}

inline void write_stl_ascii(const std::string& path, const TriangleSurface& s) {
    std::ofstream out(path);
    out.precision(17);
    out << "solid test\n";
    for (const auto& t : s.triangles) {
        out << "  facet normal 0 0 0\n    outer loop\n";
        for (int c = 0; c < 3; ++c)
            out << "      vertex " << s.points[t[c]].x() << " " << s.points[t[c]].y() << " "
                << s.points[t[c]].z() << "\n";
        out << "    endloop\n  endfacet\n";
    }
    out << "endsolid test\n";
}

}  // namespace hexmesh::test

// Test inputs for the untangler: a structured box grid split into hex corner tets.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "hexmesh/core/reference_hex.h"
#include "untangle/problem.h"

namespace hexmesh::test_support {

// n^3 unit cubes; boundary nodes fixed; interior nodes displaced uniformly in
// [-amplitude, amplitude]^3 (in cell sizes) with a fixed seed.
inline untangle::Problem displaced_grid_problem(int n, double amplitude, unsigned seed) {
    untangle::Problem p;
    const int m = n + 1;
    auto id = [m](int i, int j, int k) { return Id(i) + Id(m) * (j + Id(m) * k); };
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                const bool boundary = i == 0 || j == 0 || k == 0 || i == n || j == n || k == n;
                Vec3 x(i, j, k);
                if (!boundary) x += Vec3(u(rng), u(rng), u(rng));
                p.points.push_back(x);
                p.kinds.push_back(boundary ? VertexKind::fixed : VertexKind::interior);
            }
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const std::array<Id, 8> h = {id(i, j, k),
                                             id(i + 1, j, k),
                                             id(i + 1, j + 1, k),
                                             id(i, j + 1, k),
                                             id(i, j, k + 1),
                                             id(i + 1, j, k + 1),
                                             id(i + 1, j + 1, k + 1),
                                             id(i, j + 1, k + 1)};
                p.add_hex(h, Vec3::Ones());
            }
    p.length_scale = 1;
    return p;
}

// The hexes of a tensor grid with nodes (xs[i], ys[j], zs[k]), boundary nodes fixed, in
// VTK order, each with the box target of its own edge lengths; node (i, j, k) has id
// i + nx (j + ny k).
inline untangle::Problem tensor_grid_problem(const std::vector<double>& xs,
                                             const std::vector<double>& ys,
                                             const std::vector<double>& zs) {
    untangle::Problem p;
    const int nx = int(xs.size()), ny = int(ys.size()), nz = int(zs.size());
    auto id = [&](int i, int j, int k) { return Id(i) + Id(nx) * (j + Id(ny) * k); };
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const bool boundary =
                    i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
                p.points.emplace_back(xs[i], ys[j], zs[k]);
                p.kinds.push_back(boundary ? VertexKind::fixed : VertexKind::interior);
            }
    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i)
                p.add_hex({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                           id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                           id(i, j + 1, k + 1)},
                          Vec3(xs[i + 1] - xs[i], ys[j + 1] - ys[j], zs[k + 1] - zs[k]));
    p.length_scale = (xs.back() - xs.front()) / (nx - 1);
    return p;
}

// An unstructured hex mesh: the square [-2, 2]^2 cut into a middle square [-1, 1]^2 and four
// trapezoids around it (its corners have 3 cells around them, not 4), each patch n x n
// cells, extruded over `layers` layers 1 / n thick; boundary nodes fixed.
inline untangle::Problem o_grid_slab_problem(int n, int layers) {
    using Vec2 = Eigen::Vector2d;
    untangle::Problem p;
    std::map<std::array<long, 3>, Id> ids;  // nodes shared between patches, by position
    const auto node = [&](const Vec3& x, bool boundary) {
        const std::array<long, 3> key = {std::lround(x.x() * 1e6), std::lround(x.y() * 1e6),
                                         std::lround(x.z() * 1e6)};
        const auto [it, added] = ids.try_emplace(key, Id(p.points.size()));
        if (added) {
            p.points.push_back(x);
            p.kinds.push_back(boundary ? VertexKind::fixed : VertexKind::interior);
        }
        return it->second;
    };
    const Vec2 inner[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}},
               outer[4] = {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}};
    std::vector<std::array<Vec2, 4>> patches = {{inner[0], inner[1], inner[2], inner[3]}};
    for (int s = 0; s < 4; ++s)
        patches.push_back({inner[s], outer[s], outer[(s + 1) % 4], inner[(s + 1) % 4]});
    for (const auto& c : patches) {
        const auto at = [&](int a, int b) {  // bilinear over the patch, a along c0 -> c1
            const double u = double(a) / n, v = double(b) / n;
            return Vec2((1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] +
                        (1 - u) * v * c[3]);
        };
        for (int k = 0; k < layers; ++k)
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                    std::array<Id, 8> h;
                    const int da[4] = {0, 1, 1, 0}, db[4] = {0, 0, 1, 1};
                    for (int q = 0; q < 8; ++q) {
                        const Vec2 xy = at(a + da[q % 4], b + db[q % 4]);
                        const int z = k + q / 4;
                        const bool boundary = z == 0 || z == layers ||
                                              std::abs(std::abs(xy.x()) - 2) < 1e-9 ||
                                              std::abs(std::abs(xy.y()) - 2) < 1e-9;
                        h[q] = node(Vec3(xy.x(), xy.y(), double(z) / n), boundary);
                    }
                    p.add_hex(h, Vec3::Constant(1.0 / n));
                }
    }
    p.length_scale = 1.0 / n;
    return p;
}

}  // namespace hexmesh::test_support

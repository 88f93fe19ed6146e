// Test inputs for the untangler: a structured box grid split into hex corner tets.
#pragma once

#include <random>

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
                const std::array<Id, 8> h = {id(i, j, k),         id(i + 1, j, k),
                                             id(i + 1, j + 1, k), id(i, j + 1, k),
                                             id(i, j, k + 1),     id(i + 1, j, k + 1),
                                             id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                p.add_hex(h, Vec3::Ones());
            }
    p.length_scale = 1;
    return p;
}

}  // namespace hexmesh::test_support

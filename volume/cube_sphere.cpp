#include "volume/cube_sphere.h"

#include <cmath>

namespace hexmesh {

LatticePoint CubeSurfaceLattice::patch_point(const CubePatch& patch, int i, int j) const {
    LatticePoint p;
    p[patch.axis] = patch.max_side ? n : 0;
    p[patch.axis_i] = i;
    p[patch.axis_j] = j;
    return p;
}

CubeSurfaceLattice make_cube_surface_lattice(int n) {
    CubeSurfaceLattice s;
    s.n = n;
    s.lattice = {n + 1, n + 1, n + 1};
    s.number.assign(s.lattice.count(), -1);
    for (int c = 0; c <= n; ++c)
        for (int b = 0; b <= n; ++b)
            for (int a = 0; a <= n; ++a)
                if (a == 0 || a == n || b == 0 || b == n || c == 0 || c == n) {
                    s.number[s.lattice.flat(a, b, c)] = s.size();
                    s.points.push_back({a, b, c});
                }
    return s;
}

std::vector<std::array<Id, 4>> cube_surface_quads(const CubeSurfaceLattice& lattice) {
    const int n = lattice.n;
    std::vector<std::array<Id, 4>> quads;
    quads.reserve(6 * size_t(n) * n);
    for (const CubePatch& patch : cube_patches)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                quads.push_back({lattice.number_of(lattice.patch_point(patch, i, j)),
                                 lattice.number_of(lattice.patch_point(patch, i + 1, j)),
                                 lattice.number_of(lattice.patch_point(patch, i + 1, j + 1)),
                                 lattice.number_of(lattice.patch_point(patch, i, j + 1))});
    return quads;
}

Vec3 equiangular(const LatticePoint& p, int n) {
    constexpr double pi = 3.14159265358979323846;
    Vec3 t;
    for (int d = 0; d < 3; ++d) t[d] = std::tan(pi / 4 * (2.0 * p[d] / n - 1));
    return t;
}

Vec3 cube_ray(const Vec3& t, const Vec3& half) {
    return half.cwiseProduct(t);
}

Vec3 cube_ray(const Vec3& t, const CubeCorners& corners) {
    Vec3 w = Vec3::Zero();
    for (int c = 0; c < 8; ++c) {
        double weight = 1;
        for (int d = 0; d < 3; ++d) weight *= (c >> d & 1) ? (1 + t[d]) / 2 : (1 - t[d]) / 2;
        w += weight * corners[c];
    }
    return w;
}

Vec3 cube_sphere_ray(const LatticePoint& p, int n, const Vec3& half) {
    return cube_ray(equiangular(p, n), half);
}

Vec3 cube_sphere_ray(const LatticePoint& p, int n, const CubeCorners& corners) {
    return cube_ray(equiangular(p, n), corners);
}

}  // namespace hexmesh

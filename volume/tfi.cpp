#include "volume/tfi.h"

#include <array>

namespace hexmesh {
namespace {

// Normalized cumulative arc length of the nodes at(0..n-1) of a polyline.
template <class At>
std::vector<double> arc_length_fractions(int n, At at) {
    std::vector<double> s(n, 0.0);
    for (int m = 1; m < n; ++m) s[m] = s[m - 1] + (at(m) - at(m - 1)).norm();
    const double total = s[n - 1];
    for (int m = 0; m < n; ++m) s[m] = total > 0 ? s[m] / total : double(m) / (n - 1);
    return s;
}

}  // namespace

void fill_interior_tfi(const Block& block, std::vector<Vec3>& points) {
    const int I = block.nodes.ni - 1, J = block.nodes.nj - 1, K = block.nodes.nk - 1;
    if (I < 2 || J < 2 || K < 2) return;  // no interior node
    auto P = [&](int i, int j, int k) -> const Vec3& { return points[block.node(i, j, k)]; };

    // Edge parameters: s along i-edges at (j,k) corners, t along j-edges, u along k-edges.
    std::array<std::vector<double>, 4> s, t, u;
    for (int c = 0; c < 4; ++c) {
        const int a = c & 1, b = c >> 1;
        s[c] = arc_length_fractions(I + 1, [&](int m) { return P(m, a * J, b * K); });
        t[c] = arc_length_fractions(J + 1, [&](int m) { return P(a * I, m, b * K); });
        u[c] = arc_length_fractions(K + 1, [&](int m) { return P(a * I, b * J, m); });
    }
    auto blend = [](const std::array<std::vector<double>, 4>& e, int m, double x, double y) {
        return (1 - x) * (1 - y) * e[0][m] + x * (1 - y) * e[1][m] + (1 - x) * y * e[2][m] +
               x * y * e[3][m];
    };

    for (int k = 1; k < K; ++k) {
        for (int j = 1; j < J; ++j) {
            for (int i = 1; i < I; ++i) {
                const double fi = double(i) / I, fj = double(j) / J, fk = double(k) / K;
                const double S = blend(s, i, fj, fk), T = blend(t, j, fi, fk),
                             U = blend(u, k, fi, fj);
                const double s0 = 1 - S, t0 = 1 - T, u0 = 1 - U;
                const Vec3 faces = s0 * P(0, j, k) + S * P(I, j, k) + t0 * P(i, 0, k) +
                                   T * P(i, J, k) + u0 * P(i, j, 0) + U * P(i, j, K);
                const Vec3 edges = s0 * t0 * P(0, 0, k) + S * t0 * P(I, 0, k) +
                                   s0 * T * P(0, J, k) + S * T * P(I, J, k) + s0 * u0 * P(0, j, 0) +
                                   S * u0 * P(I, j, 0) + s0 * U * P(0, j, K) + S * U * P(I, j, K) +
                                   t0 * u0 * P(i, 0, 0) + T * u0 * P(i, J, 0) +
                                   t0 * U * P(i, 0, K) + T * U * P(i, J, K);
                const Vec3 corners = s0 * t0 * u0 * P(0, 0, 0) + S * t0 * u0 * P(I, 0, 0) +
                                     s0 * T * u0 * P(0, J, 0) + S * T * u0 * P(I, J, 0) +
                                     s0 * t0 * U * P(0, 0, K) + S * t0 * U * P(I, 0, K) +
                                     s0 * T * U * P(0, J, K) + S * T * U * P(I, J, K);
                points[block.node(i, j, k)] = faces - edges + corners;
            }
        }
    }
}

void carry_interior_tfi(const Block& block, const std::vector<Vec3>& before,
                        std::vector<Vec3>& points) {
    const Dims& d = block.nodes;
    if (d.ni < 3 || d.nj < 3 || d.nk < 3) return;  // no interior node
    std::vector<Vec3> was = before, now = points;
    fill_interior_tfi(block, was);
    fill_interior_tfi(block, now);
    for (int k = 1; k + 1 < d.nk; ++k)
        for (int j = 1; j + 1 < d.nj; ++j)
            for (int i = 1; i + 1 < d.ni; ++i) {
                const Id v = block.node(i, j, k);
                points[v] += now[v] - was[v];
            }
}

}  // namespace hexmesh

// Dihedral angles, radius ratio, signed volume and validity of tets, over a whole tet mesh.
#include "hexmesh/quality/tet_quality.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "hexmesh/quality/validity.h"

namespace hexmesh {
namespace {

constexpr int tet_edges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                 {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};  // edge a b, others c d

// Sums and extremes over a range of tets, combined in a fixed order.
struct Tally {
    Id inverted = 0, slivers = 0;
    double min_dihedral = 180, max_dihedral = 0, sum_min_dihedral = 0;
    double min_ratio = 1, sum_ratio = 0;

    void join(const Tally& o) {
        inverted += o.inverted;
        slivers += o.slivers;
        min_dihedral = std::min(min_dihedral, o.min_dihedral);
        max_dihedral = std::max(max_dihedral, o.max_dihedral);
        sum_min_dihedral += o.sum_min_dihedral;
        min_ratio = std::min(min_ratio, o.min_ratio);
        sum_ratio += o.sum_ratio;
    }
};

}  // namespace

std::array<Vec3, 4> tet_corners(const TetMesh& mesh, Id cell) {
    return {mesh.points[mesh.node(cell, 0)], mesh.points[mesh.node(cell, 1)],
            mesh.points[mesh.node(cell, 2)], mesh.points[mesh.node(cell, 3)]};
}

std::array<double, 6> dihedral_angles(const std::array<Vec3, 4>& p) {
    std::array<double, 6> angles{};
    for (int e = 0; e < 6; ++e) {
        const auto& [a, b, c, d] = tet_edges[e];
        const Vec3 axis = p[b] - p[a];
        const double len = axis.norm();
        if (!(len > 0)) continue;
        const Vec3 t = axis / len;
        // The other two vertices seen along the edge: the angle between them is the dihedral.
        Vec3 u = p[c] - p[a], v = p[d] - p[a];
        u -= u.dot(t) * t;
        v -= v.dot(t) * t;
        const double nu = u.norm(), nv = v.norm();
        if (!(nu > 0 && nv > 0)) continue;
        angles[e] = std::atan2(u.cross(v).norm(), u.dot(v)) * 180 / std::acos(-1.0);
    }
    return angles;
}

double smallest_dihedral_angle(const std::array<Vec3, 4>& p) {
    const double volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]));
    if (!(volume != 0)) return 0;  // flat
    // Unit normals of the faces opposite each point, pointing away from it (outwards): the
    // normal of the face (p[i+1], p[i+2], p[i+3]) points towards p[i] for odd i when the
    // volume is positive, for even i when it is negative.
    std::array<Vec3, 4> n;
    for (int i = 0; i < 4; ++i) {
        const Vec3& a = p[(i + 1) % 4];
        n[i] = (p[(i + 2) % 4] - a).cross(p[(i + 3) % 4] - a);
        const double length = n[i].norm();
        if (!(length > 0)) return 0;
        n[i] /= (i % 2 == 1) == (volume > 0) ? -length : length;
    }
    // The dihedral angle at the edge where faces i and j meet: cos = -n_i . n_j.
    double largest_cos = -1;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) largest_cos = std::max(largest_cos, -n[i].dot(n[j]));
    return std::acos(std::min(1.0, largest_cos)) * 180 / std::acos(-1.0);
}

double signed_volume(const std::array<Vec3, 4>& p) {
    return (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6;
}

double signed_volume(const TetMesh& mesh) {
    double v = 0;
    for (Id t = 0; t < mesh.num_cells(); ++t)
        v += signed_volume({mesh.points[mesh.node(t, 0)], mesh.points[mesh.node(t, 1)],
                            mesh.points[mesh.node(t, 2)], mesh.points[mesh.node(t, 3)]});
    return v;
}

double radius_ratio(const std::array<Vec3, 4>& p) {
    const Vec3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
    const double det = a.dot(b.cross(c));
    if (!(det > 0)) return 0;
    const double area = 0.5 * (a.cross(b).norm() + b.cross(c).norm() + c.cross(a).norm() +
                               (p[2] - p[1]).cross(p[3] - p[1]).norm());
    const double inradius = 0.5 * det / area;  // 3 V / area, V = det / 6
    const Vec3 centre = (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) +
                         c.squaredNorm() * a.cross(b)) /
                        (2 * det);
    return 3 * inradius / centre.norm();
}

TetQualityReport measure_tet_quality(const TetMesh& mesh, double sliver_degrees) {
    TetQualityReport report;
    report.cells = mesh.num_cells();
    report.points = Id(mesh.points.size());
    report.sliver_degrees = sliver_degrees;
    if (report.cells == 0) return report;
    const Tally total = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<Id>(0, report.cells, 4096), Tally{},
        [&](const tbb::blocked_range<Id>& range, Tally t) {
            for (Id cell = range.begin(); cell != range.end(); ++cell) {
                const auto p = tet_corners(mesh, cell);
                t.inverted += exact_orientation(p[0], p[1], p[2], p[3]) <= 0;
                const auto angles = dihedral_angles(p);
                const auto [lo, hi] = std::minmax_element(angles.begin(), angles.end());
                t.min_dihedral = std::min(t.min_dihedral, *lo);
                t.max_dihedral = std::max(t.max_dihedral, *hi);
                t.sum_min_dihedral += *lo;
                t.slivers += *lo < sliver_degrees;
                const double ratio = radius_ratio(p);
                t.min_ratio = std::min(t.min_ratio, ratio);
                t.sum_ratio += ratio;
            }
            return t;
        },
        [](Tally a, const Tally& b) {
            a.join(b);
            return a;
        });
    report.inverted = total.inverted;
    report.slivers = total.slivers;
    report.min_dihedral = total.min_dihedral;
    report.max_dihedral = total.max_dihedral;
    report.mean_min_dihedral = total.sum_min_dihedral / double(report.cells);
    report.min_radius_ratio = total.min_ratio;
    report.mean_radius_ratio = total.sum_ratio / double(report.cells);
    return report;
}

}  // namespace hexmesh

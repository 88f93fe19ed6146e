#include "surface/mesh_creases.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "surface/sharp_features.h"
#include "surface/surface_diagnostics.h"

namespace hexmesh {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Segments = std::vector<Kernel::Segment_3>;
using Primitive = CGAL::AABB_segment_primitive<Kernel, Segments::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 to_cgal(const Vec3& p) {
    return {p.x(), p.y(), p.z()};
}

// A triangle's plane: n . x = offset, n the unit normal out of the body.
struct Plane {
    Vec3 normal;
    double offset;
    ImplicitFunction::Piece at(const Vec3& p) const { return {normal.dot(p) - offset, normal}; }
};

}  // namespace

struct MeshCreases::Index {
    std::vector<Plane> planes;
    // Per crease edge (the order of `segments`): its end point ids and its two planes.
    std::vector<std::array<int, 2>> ends;
    std::vector<std::array<int, 2>> edge_planes;
    // Per surface point that is a corner: where it is and the planes along its creases.
    struct Corner {
        Vec3 point;
        std::vector<int> planes;
    };
    std::unordered_map<int, Corner> corners;
    Segments segments;  // must outlive the tree, which holds iterators into it
    AabbTree tree;
    double reach_per_tolerance = 1;  // 1 / sin(angle): how far a crease's planes are used
};

MeshCreases::MeshCreases(const TriangleSurface& surface, double angle_degrees,
                         const ImplicitFunction& body, double probe)
    : index_(std::make_unique<Index>()) {
    if (!(angle_degrees < 180)) return;
    Index& x = *index_;
    const FeatureCurves features = detect_sharp_features(surface, {angle_degrees, false});
    if (features.chains.empty()) return;
    constexpr double degree = 3.14159265358979323846 / 180;
    x.reach_per_tolerance = 1 / std::sin(std::clamp(angle_degrees, 1.0, 90.0) * degree);

    // Crease edges and their triangles.
    std::unordered_map<std::uint64_t, int> edge_of;
    std::vector<std::array<int, 2>> ends;
    for (const auto& chain : features.chains)
        for (size_t k = 0; k + 1 < chain.size(); ++k)
            if (edge_of.try_emplace(edge_key(chain[k], chain[k + 1]), int(ends.size())).second)
                ends.push_back({chain[k], chain[k + 1]});
    std::vector<std::array<int, 2>> edge_planes(ends.size(), {-1, -1});
    for (int t = 0; t < int(surface.triangles.size()); ++t) {
        const auto& tri = surface.triangles[t];
        int plane = -1;
        for (int e = 0; e < 3; ++e) {
            const auto it = edge_of.find(edge_key(tri[e], tri[(e + 1) % 3]));
            if (it == edge_of.end() || is_degenerate_triangle(surface, t)) continue;
            if (plane < 0) {
                const Vec3 &a = surface.points[tri[0]], &b = surface.points[tri[1]],
                           &c = surface.points[tri[2]];
                Vec3 n = (b - a).cross(c - a).normalized();
                const Vec3 centroid = (a + b + c) / 3;
                if (body.value(centroid + probe * n) < body.value(centroid - probe * n)) n = -n;
                plane = int(x.planes.size());
                x.planes.push_back({n, n.dot(a)});
            }
            auto& slots = edge_planes[it->second];
            (slots[0] < 0 ? slots[0] : slots[1]) = plane;
        }
    }
    for (int c : features.corners) x.corners[c].point = surface.points[c];
    for (size_t e = 0; e < ends.size(); ++e) {
        if (edge_planes[e][1] < 0) continue;  // not two triangles: no crease after all
        for (int end : ends[e]) {
            auto it = x.corners.find(end);
            if (it == x.corners.end()) continue;
            it->second.planes.push_back(edge_planes[e][0]);
            it->second.planes.push_back(edge_planes[e][1]);
        }
        x.ends.push_back(ends[e]);
        x.edge_planes.push_back(edge_planes[e]);
        x.segments.emplace_back(to_cgal(surface.points[ends[e][0]]),
                                to_cgal(surface.points[ends[e][1]]));
    }
    if (x.segments.empty()) return;
    x.tree.insert(x.segments.begin(), x.segments.end());
    x.tree.build();
    x.tree.accelerate_distance_queries();
}

MeshCreases::~MeshCreases() = default;

int MeshCreases::crease_edges() const {
    return int(index_->segments.size());
}

int MeshCreases::corners() const {
    return int(std::count_if(index_->corners.begin(), index_->corners.end(),
                             [](const auto& c) { return !c.second.planes.empty(); }));
}

bool MeshCreases::add_pieces(const Vec3& p, double tolerance, double value, double slack,
                             std::vector<ImplicitFunction::Piece>& out) const {
    const Index& x = *index_;
    if (x.segments.empty()) return false;
    const double tol = std::max(tolerance, 0.0), reach = x.reach_per_tolerance * tol;
    const auto hit = x.tree.closest_point_and_primitive(to_cgal(p));
    const Vec3 q(hit.first.x(), hit.first.y(), hit.first.z());
    if ((p - q).norm() > reach) return false;
    const int edge = int(hit.second - x.segments.begin());

    const std::vector<int>* planes = nullptr;  // of the nearer corner end within reach
    double corner_distance = reach;
    for (int end : x.ends[edge]) {
        const auto it = x.corners.find(end);
        if (it == x.corners.end() || it->second.planes.empty()) continue;
        const double d = (it->second.point - p).norm();
        if (d <= corner_distance) {
            planes = &it->second.planes;
            corner_distance = d;
        }
    }
    ImplicitFunction::Piece candidates[64];
    int count = 0;
    if (planes) {
        for (int k : *planes)
            if (count < 64) candidates[count++] = x.planes[k].at(p);
    } else {
        for (int k : x.edge_planes[edge]) candidates[count++] = x.planes[k].at(p);
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < count; ++i)
        if (std::abs(candidates[i].value) < std::abs(nearest)) nearest = candidates[i].value;
    // Planes of a crease elsewhere (across a thin wall, under a groove) are not this place's.
    if (!(std::abs(nearest - value) <= tol + slack)) return false;
    const size_t first = out.size();
    for (int i = 0; i < count; ++i)
        if (std::abs(candidates[i].value - nearest) <= tol) out.push_back(candidates[i]);
    if (out.size() - first >= 2) return true;
    out.resize(first);
    return false;
}

}  // namespace hexmesh

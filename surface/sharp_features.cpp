#include "surface/sharp_features.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "surface/surface_diagnostics.h"

namespace hexmesh {
namespace {

// One side of an edge: the edge (lower point id in the high half), the triangle using it and
// whether that triangle runs it from its lower to its higher point id.
struct EdgeUse {
    std::uint64_t key;
    int triangle;
    bool forward;
    bool operator<(const EdgeUse& o) const {
        return key != o.key ? key < o.key : triangle < o.triangle;
    }
};

struct FeatureEdges {
    std::vector<std::pair<int, int>> creases;       // edges of two triangles turning past the angle
    std::vector<std::pair<int, int>> boundary;      // of one or three triangles (include_boundary)
    std::vector<std::pair<int, int>> half_turning;  // of two turning by half the angle to it
};

// The uses of every edge, sorted so that those of one edge are adjacent (a parallel sort:
// faster than hashing for the million-triangle surfaces this runs on).
FeatureEdges feature_edges(const TriangleSurface& s, const FeatureOptions& o) {
    const int nt = int(s.triangles.size());
    std::vector<Vec3> normals(nt, Vec3::Zero());
    std::vector<EdgeUse> uses(3 * size_t(nt));
    tbb::parallel_for(0, nt, [&](int t) {
        const auto& tri = s.triangles[t];
        const bool degenerate = is_degenerate_triangle(s, t);
        if (!degenerate)
            normals[t] = (s.points[tri[1]] - s.points[tri[0]])
                             .cross(s.points[tri[2]] - s.points[tri[0]])
                             .normalized();
        for (int e = 0; e < 3; ++e) {
            const int a = tri[e], b = tri[(e + 1) % 3];
            // Degenerate triangles are left out: their uses sort last and are dropped.
            uses[3 * size_t(t) + e] = {degenerate ? ~std::uint64_t(0) : edge_key(a, b), t, a < b};
        }
    });
    tbb::parallel_sort(uses.begin(), uses.end());
    const double radians = o.angle_degrees * 3.14159265358979323846 / 180;
    const double cos_limit = std::cos(radians), cos_half = std::cos(0.5 * radians);
    FeatureEdges edges;
    for (size_t i = 0, j; i < uses.size() && uses[i].key != ~std::uint64_t(0); i = j) {
        for (j = i + 1; j < uses.size() && uses[j].key == uses[i].key;) ++j;
        const std::pair<int, int> edge(int(uses[i].key >> 32), int(uses[i].key & 0xffffffffu));
        if (j - i == 2) {
            const double flip = uses[i].forward == uses[i + 1].forward ? -1 : 1;
            const double c = flip * normals[uses[i].triangle].dot(normals[uses[i + 1].triangle]);
            if (c < cos_limit)
                edges.creases.push_back(edge);
            else if (c < cos_half)
                edges.half_turning.push_back(edge);
        } else if (o.include_boundary) {
            edges.boundary.push_back(edge);
        }
    }
    return edges;
}

// The chains and corners of a set of feature edges, into f: corners where 1 or at least 3
// meet, chains from corner to corner, then the closed loops.
void add_chains(const TriangleSurface& s, const std::vector<std::pair<int, int>>& edges,
                FeatureCurves& f) {
    // Incident feature edges of every point.
    std::vector<std::vector<int>> incident(s.points.size());
    for (int e = 0; e < (int)edges.size(); ++e) {
        incident[edges[e].first].push_back(e);
        incident[edges[e].second].push_back(e);
    }
    std::vector<char> is_corner(s.points.size(), 0), used(edges.size(), 0);
    for (int p = 0; p < (int)s.points.size(); ++p)
        if (!incident[p].empty() && incident[p].size() != 2) {
            is_corner[p] = 1;
            f.corners.push_back(p);
        }
    // Walks from `start` along edge `e` until a corner or back to `start`.
    auto walk = [&](int start, int e) {
        std::vector<int> chain = {start};
        int at = start;
        while (true) {
            used[e] = 1;
            at = edges[e].first == at ? edges[e].second : edges[e].first;
            chain.push_back(at);
            if (is_corner[at] || at == start) break;
            int next = -1;
            for (int c : incident[at])
                if (!used[c]) next = c;
            if (next < 0) break;
            e = next;
        }
        f.chains.push_back(std::move(chain));
    };
    for (int p : f.corners)
        for (int e : incident[p])
            if (!used[e]) walk(p, e);
    for (int e = 0; e < (int)edges.size(); ++e)  // what is left: closed loops
        if (!used[e]) walk(edges[e].first, e);
}

}  // namespace

FeatureCurves detect_sharp_features(const TriangleSurface& s, const FeatureOptions& o) {
    if (!(o.angle_degrees >= 0 && o.angle_degrees < 180))
        throw std::invalid_argument("detect_sharp_features: angle must lie in [0, 180)");
    if (!(o.noise_ratio >= 0))
        throw std::invalid_argument("detect_sharp_features: noise_ratio must be >= 0");
    FeatureEdges found = feature_edges(s, o);
    // The half-turning edges that touch a crease: the facets around the creases.
    std::vector<char> on_crease(s.points.size(), 0);
    for (const auto& [a, b] : found.creases) on_crease[a] = on_crease[b] = 1;
    FeatureCurves f;
    f.turning_edges = int(found.creases.size());
    for (const auto& [a, b] : found.half_turning)
        f.half_turning_edges += on_crease[a] || on_crease[b];
    f.noise = o.noise_ratio > 0 && f.scan_at(o.noise_ratio);
    std::vector<std::pair<int, int>> edges = std::move(found.boundary);
    if (!f.noise) edges.insert(edges.end(), found.creases.begin(), found.creases.end());
    std::sort(edges.begin(), edges.end());  // the order of the surface's edges (edge_key)
    add_chains(s, edges, f);
    return f;
}

FeatureProjection project_to_features(const TriangleSurface& s, const FeatureCurves& f,
                                      const Vec3& p) {
    FeatureProjection best;
    best.point = p;
    best.distance = std::numeric_limits<double>::infinity();
    for (int c = 0; c < (int)f.chains.size(); ++c)
        for (int k = 0; k + 1 < (int)f.chains[c].size(); ++k) {
            const Vec3& a = s.points[f.chains[c][k]];
            const Vec3 ab = s.points[f.chains[c][k + 1]] - a;
            const double len2 = ab.squaredNorm();
            const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
            const Vec3 q = a + t * ab;
            const double d = (p - q).norm();
            if (d < best.distance) best = {q, c, k, d};
        }
    return best;
}

namespace {
using SegmentKernel = CGAL::Simple_cartesian<double>;
using Segments = std::vector<SegmentKernel::Segment_3>;
using SegmentPrimitive = CGAL::AABB_segment_primitive<SegmentKernel, Segments::const_iterator>;
using SegmentTree = CGAL::AABB_tree<CGAL::AABB_traits<SegmentKernel, SegmentPrimitive>>;
}  // namespace

struct FeatureIndex::Tree {
    Segments segments;  // must outlive the tree, which holds iterators into it
    SegmentTree tree;
};

FeatureIndex::FeatureIndex(const TriangleSurface& surface, const FeatureCurves& features)
    : tree_(std::make_unique<Tree>()) {
    auto point = [&](int id) {
        const Vec3& p = surface.points[id];
        return SegmentKernel::Point_3(p.x(), p.y(), p.z());
    };
    for (int c = 0; c < int(features.chains.size()); ++c)
        for (int k = 0; k + 1 < int(features.chains[c].size()); ++k) {
            const SegmentKernel::Segment_3 segment(point(features.chains[c][k]),
                                                   point(features.chains[c][k + 1]));
            if (segment.is_degenerate()) continue;
            tree_->segments.push_back(segment);
            segments_.push_back({c, k});
        }
    if (segments_.empty()) return;
    tree_->tree.insert(tree_->segments.begin(), tree_->segments.end());
    tree_->tree.build();
    tree_->tree.accelerate_distance_queries();
    tree_->tree.closest_point(tree_->segments[0].source());  // builds the search structure now
}

FeatureIndex::~FeatureIndex() = default;

FeatureProjection FeatureIndex::project(const Vec3& p) const {
    FeatureProjection r;
    r.point = p;
    r.distance = std::numeric_limits<double>::infinity();
    if (segments_.empty()) return r;
    const auto hit =
        tree_->tree.closest_point_and_primitive(SegmentKernel::Point_3(p.x(), p.y(), p.z()));
    r.point = Vec3(hit.first.x(), hit.first.y(), hit.first.z());
    std::tie(r.chain, r.segment) = segments_[size_t(hit.second - tree_->segments.begin())];
    r.distance = (r.point - p).norm();
    return r;
}

}  // namespace hexmesh

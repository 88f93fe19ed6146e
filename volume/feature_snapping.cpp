#include "volume/feature_snapping.h"

#include <tbb/parallel_for.h>

#include <limits>
#include <map>
#include <optional>
#include <set>

#include "hexmesh/core/reference_hex.h"
#include "surface/implicit_features.h"

namespace hexmesh {
namespace {

// Shortest edge between two slip nodes at each slip node (+inf elsewhere).
std::vector<double> shortest_wall_edge(const BlockGrid& grid) {
    std::vector<double> shortest(grid.points.size(), std::numeric_limits<double>::infinity());
    for (const Block& block : grid.blocks)
        for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
            for (const auto& e : hex_edges) {
                const Id a = nodes[e[0]], b = nodes[e[1]];
                if (grid.kinds[a] != VertexKind::slip || grid.kinds[b] != VertexKind::slip) continue;
                const double length = (grid.points[a] - grid.points[b]).norm();
                shortest[a] = std::min(shortest[a], length);
                shortest[b] = std::min(shortest[b], length);
            }
        });
    return shortest;
}

// A corner's key: its position rounded to 1e-3 h, so one corner reached from several nodes
// counts once.
std::array<long long, 3> corner_key(const Vec3& c, double h) {
    return {std::llround(c.x() / (1e-3 * h)), std::llround(c.y() / (1e-3 * h)),
            std::llround(c.z() / (1e-3 * h))};
}

// The corner snap_to_corner finds from x (a point classified as a corner within `reach`), if
// it is one (within 1e-6 h) and within reach.
std::optional<Vec3> corner_within(const ImplicitFunction& body, const Vec3& x, double h,
                                  double reach) {
    const Vec3 c = snap_to_corner(body, x, h);
    if (classify_surface_point(body, c, 1e-6 * h) != FeatureKind::corner) return std::nullopt;
    if ((c - x).norm() > reach) return std::nullopt;
    return c;
}

}  // namespace

std::vector<Vec3> body_corners_near(const ImplicitFunction& body, const std::vector<Vec3>& points,
                                    double reach) {
    std::vector<std::optional<Vec3>> found(points.size());
    tbb::parallel_for(size_t(0), points.size(),
                      [&](size_t v) {
                          if (classify_surface_point(body, points[v], reach) == FeatureKind::corner)
                              found[v] = corner_within(body, points[v], reach, reach);
                      });
    std::set<std::array<long long, 3>> seen;
    std::vector<Vec3> corners;
    for (const std::optional<Vec3>& c : found)
        if (c && seen.insert(corner_key(*c, reach)).second) corners.push_back(*c);
    return corners;
}

FeatureSnapping snap_to_features(BlockGrid& grid, const ImplicitFunction& body, double fraction) {
    const std::vector<double> shortest = shortest_wall_edge(grid);
    FeatureSnapping result;
    // Corners first: each keeps its nearest node, keyed by the rounded corner position.
    struct Claim {
        Id node;
        double distance;
        Vec3 point;
    };
    std::map<std::array<long long, 3>, Claim> corners;
    std::vector<Id> crease_candidates;
    for (size_t v = 0; v < grid.points.size(); ++v) {
        if (grid.kinds[v] != VertexKind::slip) continue;
        const double h = shortest[v], reach = fraction * h;
        const Vec3& x = grid.points[v];
        const FeatureKind kind = classify_surface_point(body, x, reach);
        if (kind == FeatureKind::smooth) continue;
        crease_candidates.push_back(Id(v));
        if (kind != FeatureKind::corner) continue;
        const std::optional<Vec3> c = corner_within(body, x, h, reach);
        if (!c) continue;
        const double d = (*c - x).norm();
        auto [it, added] = corners.try_emplace(corner_key(*c, h), Claim{Id(v), d, *c});
        if (!added && d < it->second.distance) it->second = {Id(v), d, *c};
    }
    std::vector<bool> is_corner(grid.points.size(), false);
    for (const auto& [key, claim] : corners) {
        grid.points[claim.node] = claim.point;
        grid.kinds[claim.node] = VertexKind::corner;
        is_corner[claim.node] = true;
        ++result.corner_nodes;
    }
    for (Id v : crease_candidates) {
        if (is_corner[v]) continue;
        const double h = shortest[v];
        const Vec3 p = project_to_crease(body, grid.points[v], h);
        if ((p - grid.points[v]).norm() > fraction * h ||
            classify_surface_point(body, p, 1e-6 * h) == FeatureKind::smooth)
            continue;
        grid.points[v] = p;
        grid.kinds[v] = VertexKind::feature_edge;
        ++result.crease_nodes;
    }
    return result;
}

std::optional<CubeCorners> body_corners_by_octant(const Vec3& centre,
                                                  const std::vector<Vec3>& found, double h) {
    if (found.size() != 8) return std::nullopt;
    CubeCorners corners;
    std::array<bool, 8> taken{};
    for (const Vec3& c : found) {
        const Vec3 r = c - centre;
        if ((r.cwiseAbs().array() < 1e-3 * h).any()) return std::nullopt;  // on an axis plane
        const int octant = (r.x() > 0) + 2 * (r.y() > 0) + 4 * (r.z() > 0);
        if (taken[octant]) return std::nullopt;
        taken[octant] = true;
        corners[octant] = r;
    }
    return corners;
}

std::optional<CubeCorners> corners_near_wall(const ImplicitFunction& body, const Vec3& centre,
                                             const std::vector<Vec3>& wall, double h) {
    return body_corners_by_octant(centre, body_corners_near(body, wall, h), h);
}

}  // namespace hexmesh

#include "volume/feature_snapping.h"

#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
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
                if (grid.kinds[a] != VertexKind::slip || grid.kinds[b] != VertexKind::slip)
                    continue;
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
    tbb::parallel_for(size_t(0), points.size(), [&](size_t v) {
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

namespace {

// The octant of f (coordinates in a frame around the centre), entry (f.x > 0) + 2 (f.y > 0) +
// 4 (f.z > 0) as the cube's corners; -1 within 1e-3 h of one of the frame's planes.
int octant_of(const Vec3& f, double h) {
    if ((f.cwiseAbs().array() < 1e-3 * h).any()) return -1;
    return (f.x() > 0) + 2 * (f.y() > 0) + 4 * (f.z() > 0);
}

// The corners `found` as the cube's, one per octant of the frame `axes` (columns: where the
// cube's x, y, z go) around the centre, none within 1e-3 h of its planes; nullopt otherwise.
std::optional<CubeCorners> by_octant(const Vec3& centre, const std::vector<Vec3>& found,
                                     const Mat3& axes, double h) {
    CubeCorners corners;
    std::array<bool, 8> taken{};
    for (const Vec3& c : found) {
        const Vec3 r = c - centre, f = axes.transpose() * r;
        const int octant = octant_of(f, h);
        if (octant < 0) return std::nullopt;  // on a frame plane
        if (taken[octant]) return std::nullopt;
        taken[octant] = true;
        corners[octant] = r;
    }
    return corners;
}

// The edge directions of 8 points that are the corners of a box at any angle: the three
// mutually orthogonal directions along each of which 4 pairs of the points lie, as far apart
// (face and body diagonals join fewer pairs), as a right-handed frame, each column the one
// nearest a world axis and pointing along it; nullopt for other points.
std::optional<Mat3> box_axes(const std::vector<Vec3>& p, double h) {
    std::vector<Vec3> edges;  // a direction with its length
    for (size_t i = 0; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j) {
            const Vec3 d = p[j] - p[i];
            int parallel = 0;
            for (size_t k = 0; k < p.size(); ++k)
                for (size_t l = k + 1; l < p.size(); ++l) {
                    const Vec3 e = p[l] - p[k];
                    parallel += (e - d).norm() < 1e-3 * h || (e + d).norm() < 1e-3 * h;
                }
            const bool known = std::any_of(edges.begin(), edges.end(), [&](const Vec3& e) {
                return (e - d).norm() < 1e-3 * h || (e + d).norm() < 1e-3 * h;
            });
            if (parallel == 4 && !known) edges.push_back(d);
        }
    if (edges.size() != 3) return std::nullopt;
    for (Vec3& e : edges) e.normalize();
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
            if (std::abs(edges[a].dot(edges[b])) > 1e-3) return std::nullopt;
    Mat3 axes;
    std::array<bool, 3> used{};
    for (int a = 0; a < 3; ++a) {  // world axis a takes the edge direction nearest it
        int best = -1;
        for (int e = 0; e < 3; ++e)
            if (!used[e] && (best < 0 || std::abs(edges[e][a]) > std::abs(edges[best][a])))
                best = e;
        used[best] = true;
        axes.col(a) = edges[best][a] < 0 ? Vec3(-edges[best]) : edges[best];
    }
    if (axes.determinant() < 0) axes.col(2) *= -1;
    return axes;
}

// The smallest of the 8 corner volumes of the hexahedron whose corners are `corners`
// (CubeCorners order; the determinant of the three edges from a corner): <= 0 when twisted,
// largest for a large box.
double smallest_corner_volume(const CubeCorners& corners) {
    double smallest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c) {
        Mat3 edges;
        for (int a = 0; a < 3; ++a) edges.col(a) = corners[c ^ (1 << a)] - corners[c];
        const int flips = (c & 1) + ((c >> 1) & 1) + ((c >> 2) & 1);  // edges pointing back
        smallest = std::min(smallest, (flips % 2 == 0 ? 1 : -1) * edges.determinant());
    }
    return smallest;
}

// Whether corners, as the cube's, make a hexahedron whose 8 corner tets are all positive: cube
// edges on the body's edges, not across its faces (a cube turned 60 degrees about (1, 1, 1)
// has one corner in each octant, but octants 0 and 1 hold two ends of a face diagonal).
bool untwisted(const CubeCorners& corners) {
    return smallest_corner_volume(corners) > 0;
}

}  // namespace

std::optional<CubeCorners> body_corners_by_octant(const Vec3& centre,
                                                  const std::vector<Vec3>& found, double h) {
    if (found.size() != 8) return std::nullopt;
    std::optional<CubeCorners> corners = by_octant(centre, found, Mat3::Identity(), h);
    if (corners && untwisted(*corners)) return corners;
    // A box at an angle whose corners share the world's octants, or fill them twisted: the
    // octants of its own axes.
    if (const std::optional<Mat3> axes = box_axes(found, h)) {
        corners = by_octant(centre, found, *axes, h);
        if (corners && untwisted(*corners)) return corners;
    }
    return std::nullopt;
}

std::optional<CubeCorners> corners_near_wall(const ImplicitFunction& body, const Vec3& centre,
                                             const std::vector<Vec3>& wall, double h) {
    return body_corners_by_octant(centre, body_corners_near(body, wall, h), h);
}

double inside_share(const ImplicitFunction& body, const Vec3& x, double r) {
    constexpr int m = 6;
    int inside = 0;
    for (int face = 0; face < 6; ++face)
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < m; ++j) {
                Vec3 d;
                d[face / 2] = face % 2 ? 1 : -1;
                d[(face / 2 + 1) % 3] = -1 + (2 * i + 1.0) / m;
                d[(face / 2 + 2) % 3] = -1 + (2 * j + 1.0) / m;
                inside += body.value(x + r * d.normalized()) < 0;
            }
    return inside / double(6 * m * m);
}

std::optional<CubeCorners> convex_corners_by_octant(const ImplicitFunction& body,
                                                    const Vec3& centre,
                                                    const std::vector<Vec3>& found, double h) {
    std::array<std::vector<Vec3>, 8> candidates;  // per octant, relative to the centre
    for (const Vec3& c : found) {
        const Vec3 r = c - centre;
        const int octant = octant_of(r, h);
        if (octant < 0 || !(inside_share(body, c, 0.25 * h) < 0.2)) continue;
        candidates[octant].push_back(r);
    }
    long long choices = 1;
    for (const std::vector<Vec3>& in_octant : candidates) {
        choices *= static_cast<long long>(in_octant.size());
        if (choices == 0 || choices > (1 << 20)) return std::nullopt;
    }
    // Per cube edge (corner c to c + its bit a), per pair of candidates at its ends: whether
    // the segment between them lies on the body's surface (15 points along it within 0.05 h,
    // or 0.002 of the bounds' diagonal, of u = 0: a surface file's distance field is off by a
    // fraction of its voxel of 1/256 of the extent along an edge, and is cut off 3 voxels out;
    // one point may miss), as the patch edge then does.
    const auto on_surface = [&](const Vec3& p, const Vec3& q) {
        constexpr int samples = 16;
        const double near = std::max(0.05 * h, 2e-3 * body.bounds().diagonal());
        int off = 0;
        for (int s = 1; s < samples; ++s)
            off += !(std::abs(body.value(centre + p + (q - p) * (s / double(samples)))) < near);
        return off <= 1;
    };
    std::array<std::array<std::vector<bool>, 3>, 8> edge_on;  // [c][a]: entry i * size + j
    for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) {
            if (c & (1 << a)) continue;
            const std::vector<Vec3>&from = candidates[c], &to = candidates[c | (1 << a)];
            for (const Vec3& p : from)
                for (const Vec3& q : to) edge_on[c][a].push_back(on_surface(p, q));
        }
    std::optional<CubeCorners> best;
    double largest = 0;  // only untwisted hexahedra
    for (long long k = 0; k < choices; ++k) {
        CubeCorners corners;
        std::array<size_t, 8> pick;
        long long rest = k;
        for (int o = 0; o < 8; ++o) {
            const long long size = static_cast<long long>(candidates[o].size());
            pick[o] = size_t(rest % size);
            corners[o] = candidates[o][pick[o]];
            rest /= size;
        }
        bool edges_on_surface = true;
        for (int c = 0; c < 8 && edges_on_surface; ++c)
            for (int a = 0; a < 3 && edges_on_surface; ++a)
                if (!(c & (1 << a)))
                    edges_on_surface = edge_on[c][a][pick[c] * candidates[c | (1 << a)].size() +
                                                     pick[c | (1 << a)]];
        if (!edges_on_surface) continue;
        const double volume = smallest_corner_volume(corners);
        if (volume > largest) largest = volume, best = corners;
    }
    return best;
}

std::optional<CubeCorners> corners_at_patch_corners(const ImplicitFunction& body,
                                                    const Vec3& centre,
                                                    const std::array<Vec3, 8>& at, double h) {
    CubeCorners corners;
    for (int c = 0; c < 8; ++c) {
        if (classify_surface_point(body, at[c], 1e-6 * h) != FeatureKind::corner)
            return std::nullopt;
        corners[c] = at[c] - centre;
    }
    if (!untwisted(corners)) return std::nullopt;
    return corners;
}

}  // namespace hexmesh

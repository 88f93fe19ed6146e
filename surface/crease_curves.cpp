#include "surface/crease_curves.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "surface/implicit_features.h"

namespace hexmesh {

namespace {

using Piece = ImplicitFunction::Piece;
using Polyline = std::vector<Vec3>;

// Lengths in units of step.
constexpr double feature_tolerance = 1e-6;  // pieces this near zero meet at a point
constexpr double vanish_tolerance = 1e-9;   // |u| at an accepted crease point or corner
constexpr double seed_window = 2;           // lattice points with distinct pieces this near seed
constexpr double corner_reach = 1.5;        // a corner (or the loop's start) this near, within
constexpr double ahead_cosine = 0.8;        // this cone around the tangent, ends a trace
constexpr double min_advance = 0.25;        // a step advancing less ends a trace; shortest segment
constexpr double max_move = 2;              // a step moving farther ends a trace
constexpr double snap_reach = 2;            // a trace that fades out ends at a corner this near
constexpr double cover_radius = 1;          // traced points cover the seeds this near with
constexpr double cover_cosine = 0.9;        // tangents this parallel: no second trace there
constexpr double max_steps_per_diagonal = 50;  // step cap of one trace, per bounds diagonal
constexpr int min_loop_steps = 3;              // a loop closes after at least this many steps
constexpr double max_lattice_points = 1e9;

struct Seed {
    Vec3 point;    // on a crease
    Vec3 tangent;  // unit, crease_tangent there
    bool used = false;
};

// True when q lies on u = 0 and the pieces active there all vanish and make `kind`: a genuine
// crease point or corner, not a place where the pieces' zero sets merely cross off the surface.
bool is_feature_point(const ImplicitFunction& u, const Vec3& q, double step, FeatureKind kind) {
    if (!q.allFinite() || !(std::abs(u.value(q)) < vanish_tolerance * step)) return false;
    const double tolerance = feature_tolerance * step;
    std::vector<Piece> pieces;
    u.active_pieces(q, tolerance, pieces);
    for (const Piece& piece : pieces)
        if (!(std::abs(piece.value) <= 2 * tolerance)) return false;
    return classify_surface_point(u, q, tolerance) == kind;
}

// Index of the corner within feature_tolerance of c, appending c when there is none.
int add_corner(std::vector<Vec3>& corners, const Vec3& c, double step) {
    for (std::size_t i = 0; i < corners.size(); ++i)
        if ((corners[i] - c).norm() < feature_tolerance * step) return static_cast<int>(i);
    corners.push_back(c);
    return static_cast<int>(corners.size()) - 1;
}

// The nearest corner that a trace at x heading along t reaches within corner_reach: -1 if none.
// The crease must join them: the midpoint of x and the corner projects onto a crease point
// near it.
int corner_ahead(const ImplicitFunction& u, const std::vector<Vec3>& corners, const Vec3& x,
                 const Vec3& t, double step) {
    std::vector<std::pair<double, int>> candidates;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const Vec3 d = corners[i] - x;
        const double distance = d.norm();
        if (distance < corner_reach * step && d.dot(t) > ahead_cosine * distance)
            candidates.push_back({distance, static_cast<int>(i)});
    }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [distance, i] : candidates) {
        const Vec3 mid = 0.5 * (x + corners[i]);
        const Vec3 q = project_to_crease(u, mid, step);
        if ((q - mid).norm() < 0.25 * distance && is_feature_point(u, q, step, FeatureKind::crease))
            return i;
    }
    return -1;
}

bool contains(const Box3& box, const Vec3& p) {
    return (p.array() >= box.lo.array()).all() && (p.array() <= box.hi.array()).all();
}

// Seeds bucketed in cubes of side `cell`: the seeds within one cell of a point lie in the 27
// cubes around the point's cube.
struct SeedGrid {
    Vec3 origin;
    double cell;
    std::unordered_map<std::int64_t, std::vector<int>> buckets;
};

// 21 bits per axis; indices beyond are clamped (only the buckets' sizes suffer).
std::int64_t cell_key(std::int64_t i, std::int64_t j, std::int64_t k) {
    auto clamp = [](std::int64_t a) {
        return std::clamp<std::int64_t>(a, 0, (std::int64_t(1) << 21) - 1);
    };
    return (clamp(i) << 42) | (clamp(j) << 21) | clamp(k);
}

Eigen::Matrix<std::int64_t, 3, 1> cell_of(const SeedGrid& grid, const Vec3& p) {
    const Vec3 c = ((p - grid.origin) / grid.cell).array().floor();
    return c.cwiseMax(-1.0).cwiseMin(1e9).cast<std::int64_t>();
}

SeedGrid bucket_seeds(const std::vector<Seed>& seeds, const Box3& region, double step) {
    SeedGrid grid{region.lo - Vec3::Constant(4 * step), step, {}};
    for (std::size_t s = 0; s < seeds.size(); ++s) {
        const auto c = cell_of(grid, seeds[s].point);
        grid.buckets[cell_key(c[0], c[1], c[2])].push_back(static_cast<int>(s));
    }
    return grid;
}

// Marks the seeds that `line` passes within cover_radius of, along their tangent.
void cover_seeds(const Polyline& line, double step, const SeedGrid& grid,
                 std::vector<Seed>& seeds) {
    const std::size_t n = line.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 along = (line[std::min(i + 1, n - 1)] - line[i > 0 ? i - 1 : 0]).normalized();
        const auto c = cell_of(grid, line[i]);
        for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj)
                for (int dk = -1; dk <= 1; ++dk) {
                    const auto found = grid.buckets.find(cell_key(c[0] + di, c[1] + dj, c[2] + dk));
                    if (found == grid.buckets.end()) continue;
                    for (int s : found->second) {
                        Seed& seed = seeds[s];
                        if ((seed.point - line[i]).norm() <= cover_radius * step &&
                            std::abs(seed.tangent.dot(along)) > cover_cosine)
                            seed.used = true;
                    }
                }
    }
}

struct Trace {
    Polyline points;
    bool closed = false;  // back at the start, which ends `points` again
};

// Follows the crease through `start` along `direction`: steps of `step` along the crease
// tangent, each projected back onto the crease. Ends exactly at the first corner reached, at
// `start` when the crease closes (only if may_close), else where the next step leaves the
// crease, the region or the step cap; there, at a corner that snap_to_corner finds within
// snap_reach ahead (added to corners), if any.
Trace follow_crease(const ImplicitFunction& u, const Vec3& start, const Vec3& direction,
                    double step, const Box3& region, int max_steps, bool may_close,
                    std::vector<Vec3>& corners) {
    Trace trace;
    trace.points.push_back(start);
    Vec3 x = start;
    Vec3 t = direction;
    for (int k = 0; k < max_steps; ++k) {
        const int c = corner_ahead(u, corners, x, t, step);
        if (c >= 0) {
            trace.points.push_back(corners[c]);
            return trace;
        }
        const Vec3 back = start - x;
        if (may_close && k >= min_loop_steps && back.norm() < corner_reach * step &&
            back.dot(t) > ahead_cosine * back.norm()) {
            trace.points.push_back(start);
            trace.closed = true;
            return trace;
        }
        const Vec3 y = project_to_crease(u, x + step * t, step);
        const Vec3 move = y - x;
        if (!(move.dot(t) > min_advance * step) || !(move.norm() < max_move * step) ||
            !contains(region, y) || !is_feature_point(u, y, step, FeatureKind::crease))
            break;
        Vec3 next = crease_tangent(u, y, feature_tolerance * step);
        if (next.dot(t) < 0) next = -next;
        trace.points.push_back(y);
        x = y;
        t = next;
    }
    const Vec3 c = snap_to_corner(u, x, step);
    const Vec3 d = c - x;
    if (!(d.norm() < snap_reach * step) || d.dot(t) < 0 ||
        !is_feature_point(u, c, step, FeatureKind::corner))
        return trace;
    const Vec3& corner = corners[add_corner(corners, c, step)];
    if (d.norm() >= min_advance * step)
        trace.points.push_back(corner);
    else if (trace.points.size() > 1)
        trace.points.back() = corner;  // keeps the last segment from shrinking to nothing
    return trace;
}

// Drops the interior points nearer than min_advance step to the point kept before them or to
// the last point: only a crease that short keeps a segment that short.
Polyline drop_short_segments(const Polyline& line, double step) {
    const double shortest = min_advance * step;
    Polyline kept{line.front()};
    for (std::size_t i = 1; i + 1 < line.size(); ++i)
        if ((line[i] - kept.back()).norm() >= shortest &&
            (line[i] - line.back()).norm() >= shortest)
            kept.push_back(line[i]);
    kept.push_back(line.back());
    return kept;
}

// The unit n_a x n_b and its opposite for each pair of distinct normals active at a corner:
// the directions in which creases may leave it.
std::vector<Vec3> crease_directions(const ImplicitFunction& u, const Vec3& corner, double step) {
    static const double min_sine = std::sin(same_normal_degrees * std::acos(-1.0) / 180);
    std::vector<Piece> pieces;
    u.active_pieces(corner, feature_tolerance * step, pieces);
    std::vector<Vec3> normals;
    for (const Piece& piece : pieces) {
        const double length = piece.gradient.norm();
        if (std::isfinite(length) && length > 0) normals.push_back(piece.gradient / length);
    }
    std::vector<Vec3> directions;
    for (std::size_t i = 0; i < normals.size(); ++i)
        for (std::size_t j = i + 1; j < normals.size(); ++j) {
            const Vec3 c = normals[i].cross(normals[j]);
            if (!(c.norm() > min_sine)) continue;
            directions.push_back(c.normalized());
            directions.push_back(-c.normalized());
        }
    return directions;
}

// True when one of `lines` starts or ends at `corner` (bitwise) heading about along `direction`.
bool leaves_along(const std::vector<Polyline>& lines, const Vec3& corner, const Vec3& direction) {
    for (const Polyline& line : lines) {
        const std::size_t n = line.size();
        if (line[0] == corner && (line[1] - line[0]).normalized().dot(direction) > cover_cosine)
            return true;
        if (line[n - 1] == corner &&
            (line[n - 2] - line[n - 1]).normalized().dot(direction) > cover_cosine)
            return true;
    }
    return false;
}

}  // namespace

CreaseCurves trace_creases(const ImplicitFunction& body, double step) {
    if (!(step > 0) || !std::isfinite(step))
        throw std::invalid_argument("trace_creases: step must be positive, got " +
                                    std::to_string(step));
    const Box3 bounds = body.bounds();
    const Box3 lattice_box{bounds.lo - Vec3::Constant(step), bounds.hi + Vec3::Constant(step)};
    const Box3 region{bounds.lo - Vec3::Constant(2 * step), bounds.hi + Vec3::Constant(2 * step)};
    std::int64_t counts[3];
    Vec3 spacing;
    double total = 1;
    for (int a = 0; a < 3; ++a) {
        const double size = lattice_box.size()[a];
        const double n = std::ceil(size / step) + 1;
        total *= n;
        if (!(total < max_lattice_points))
            throw std::invalid_argument("trace_creases: step " + std::to_string(step) +
                                        " is too small for a body of " + "bounding diagonal " +
                                        std::to_string(bounds.diagonal()) +
                                        " (the seed lattice would exceed 1e9 points)");
        counts[a] = static_cast<std::int64_t>(n);
        spacing[a] = n > 1 ? size / (n - 1) : 0;
    }

    CreaseCurves result;
    std::vector<Seed> seeds;
    for (std::int64_t i = 0; i < counts[0]; ++i)
        for (std::int64_t j = 0; j < counts[1]; ++j)
            for (std::int64_t k = 0; k < counts[2]; ++k) {
                const Vec3 p = lattice_box.lo + Vec3(i, j, k).cwiseProduct(spacing);
                if (!(std::abs(body.value(p)) < step)) continue;
                const FeatureKind kind = classify_surface_point(body, p, seed_window * step);
                if (kind == FeatureKind::smooth) continue;
                if (kind == FeatureKind::corner) {
                    const Vec3 c = snap_to_corner(body, p, step);
                    if (is_feature_point(body, c, step, FeatureKind::corner))
                        add_corner(result.corners, c, step);
                }
                const Vec3 q = project_to_crease(body, p, step);
                if (is_feature_point(body, q, step, FeatureKind::crease))
                    seeds.push_back({q, crease_tangent(body, q, feature_tolerance * step)});
            }

    const SeedGrid grid = bucket_seeds(seeds, region, step);
    const int max_steps =
        static_cast<int>(std::ceil(max_steps_per_diagonal * region.diagonal() / step)) + 100;
    for (Seed& seed : seeds) {
        if (seed.used) continue;
        seed.used = true;
        const Trace forward = follow_crease(body, seed.point, seed.tangent, step, region, max_steps,
                                            true, result.corners);
        Polyline line;
        if (forward.closed) {
            line = forward.points;
        } else {
            const Trace backward = follow_crease(body, seed.point, -seed.tangent, step, region,
                                                 max_steps, false, result.corners);
            line.assign(backward.points.rbegin(), backward.points.rend());
            line.insert(line.end(), forward.points.begin() + 1, forward.points.end());
        }
        if (line.size() < 2) continue;
        cover_seeds(line, step, grid, seeds);
        result.polylines.push_back(drop_short_segments(line, step));
    }
    // Creases that no seed reached (too short to hold one): traced from their corners. The
    // corners may grow meanwhile.
    for (std::size_t c = 0; c < result.corners.size(); ++c) {
        const Vec3 corner = result.corners[c];
        for (const Vec3& direction : crease_directions(body, corner, step)) {
            if (leaves_along(result.polylines, corner, direction)) continue;
            const Trace trace = follow_crease(body, corner, direction, step, region, max_steps,
                                              false, result.corners);
            if (trace.points.size() < 2) continue;
            result.polylines.push_back(drop_short_segments(trace.points, step));
        }
    }
    return result;
}

}  // namespace hexmesh

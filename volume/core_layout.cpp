#include "volume/core_layout.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include "surface/implicit_features.h"
#include "volume/cube_sphere.h"
#include "volume/surface_placement.h"

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;

// tan(pi/4 (2 m/n - 1)): the equiangular coordinate of lattice index m.
double equiangular_index(int m, int n) {
    return std::tan(pi / 4 * (2.0 * m / n - 1));
}

Vec3 unit(int axis) {
    return Vec3::Unit(axis);
}

// Arc length along a polyline of wall points, at each point.
std::vector<double> arc_lengths(const std::vector<Vec3>& p) {
    std::vector<double> s(p.size(), 0.0);
    for (size_t i = 1; i < p.size(); ++i) s[i] = s[i - 1] + (p[i] - p[i - 1]).norm();
    return s;
}

// Linear interpolation of ys at x in the increasing table xs (clamped at its ends).
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    if (x <= xs.front()) return ys.front();
    if (x >= xs.back()) return ys.back();
    const size_t i = std::upper_bound(xs.begin(), xs.end(), x) - xs.begin();
    const double f = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return ys[i - 1] + f * (ys[i] - ys[i - 1]);
}

// Cells per segment of the given lengths: at least one each, `cells` in all, the rest
// shared in proportion to length (largest remainder).
std::vector<int> share_cells(const std::vector<double>& lengths, int cells) {
    const int m = int(lengths.size());
    double total = 0;
    for (double x : lengths) total += std::max(x, 0.0);
    std::vector<int> count(m, 1);
    std::vector<double> want(m);
    for (int i = 0; i < m; ++i)  // no length at all: shared evenly
        want[i] = (cells - m) * (total > 0 ? std::max(lengths[i], 0.0) / total : 1.0 / m);
    for (int i = 0; i < m; ++i) count[i] += int(std::floor(want[i]));
    int left = cells - std::accumulate(count.begin(), count.end(), 0);
    std::vector<int> order(m);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return want[a] - std::floor(want[a]) > want[b] - std::floor(want[b]);
    });
    for (int i = 0; left > 0; i = (i + 1) % m, --left) ++count[order[i]];
    return count;
}

// Where the half-line t = w d + end (0 < w < 1) meets the crease near the wall point `near`
// (sampled at w = `sampled`): the crease point nearest `near` (the corner, when `corner`), and
// the w whose ray passes through it, by Gauss-Newton on the ray's direction (cube_ray is
// trilinear in t: affine in w along the faces' axes, one step; quadratic along their
// diagonals); `sampled` when that w is not within 0.01 of it.
double crease_on_half_line(const ImplicitFunction& body, const Vec3& centre,
                           const std::function<Vec3(const Vec3&)>& ray, const Vec3& d,
                           const Vec3& end, const Vec3& near, double sampled, bool corner,
                           double length_scale) {
    const Vec3 q = (corner ? snap_to_corner(body, near, length_scale)
                           : project_to_crease(body, near, length_scale)) -
                   centre;
    double w = sampled;
    for (int step = 0; step < 4; ++step) {
        constexpr double dw = 1e-4;
        const Vec3 at = ray(w * d + end);
        const Vec3 slope = (ray((w + dw) * d + end) - ray((w - dw) * d + end)) / (2 * dw);
        const Vec3 qs = q.cross(slope);  // q x (at + x slope) = 0 in the least-squares sense
        if (!(qs.squaredNorm() > 0)) return sampled;
        w -= q.cross(at).dot(qs) / qs.squaredNorm();
    }
    return std::abs(w - sampled) < 0.01 ? w : sampled;
}

// Lowers each ring's roundness as far as needed for the rings to stay nested: a round ring
// reaches less far along the diagonals than a square one, so each ring's diagonal reach must
// exceed the previous ring's by at least a quarter of its step along the axes.
void keep_rings_nested(AxialRings& rings) {
    const double root2 = std::sqrt(2.0);
    double previous =
        root2 * rings.radius[0] * (1 - rings.roundness[0]) + rings.radius[0] * rings.roundness[0];
    for (int s = 1; s <= rings.cells(); ++s) {
        const double w = rings.radius[s];
        const double least = previous + 0.25 * (w - rings.radius[s - 1]);
        const double most_round = (root2 - least / w) / (root2 - 1);
        rings.roundness[s] = std::clamp(std::min(rings.roundness[s], most_round), 0.0, 1.0);
        previous = w * (root2 - rings.roundness[s] * (root2 - 1));
    }
}

}  // namespace

CoreLayout one_block_core(int n) {
    CoreLayout core;
    Block block{"core", {n + 1, n + 1, n + 1}, {}, {}};
    block.node_ids.resize(block.nodes.count());
    std::iota(block.node_ids.begin(), block.node_ids.end(), Id(0));
    core.t.resize(block.nodes.count());
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                core.t[block.nodes.flat(i, j, k)] = equiangular({i, j, k}, n);
    core.blocks.push_back(std::move(block));
    for (int side = 0; side < 6; ++side) {
        const CubePatch& patch = cube_patches[side];
        core.wall_faces.push_back({0, BlockFace(2 * patch.axis + patch.max_side), side});
    }
    std::sort(core.wall_faces.begin(), core.wall_faces.end(),
              [](const auto& a, const auto& b) { return a.face < b.face; });
    return core;
}

AxialRings even_axial_rings(int axis, int cells, double outer) {
    AxialRings rings;
    rings.axis = axis;
    const double column = outer / 2;
    for (int s = 0; s <= cells; ++s) {
        rings.radius.push_back(s == cells ? outer : column + (outer - column) * s / cells);
        rings.roundness.push_back(s == 0 || s == cells ? 0.0 : std::sin(pi * s / cells));
    }
    keep_rings_nested(rings);
    return rings;
}

AxialCreases find_axial_creases(const ImplicitFunction& body, const Vec3& centre,
                                const std::function<Vec3(const Vec3&)>& ray, int axis, double outer,
                                double length_scale) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    constexpr int samples = 512;
    AxialCreases found;
    for (int i = 0; i < samples; ++i) found.w.push_back((i + 0.5) / samples);
    // The creases met along one half-line t = w dir + end, as the middles of runs of samples
    // classified sharp, each then located exactly; those next to the face's centre or its
    // frame (a tip, the patch edges) are not rings.
    auto creases_along = [&](const Vec3& dir, const Vec3& end, std::vector<Vec3>& p) {
        std::vector<double> creases;
        p.resize(samples);
        for (int i = 0; i < samples; ++i)
            p[i] = place_on_surface(body, centre, ray(found.w[i] * dir + end), length_scale);
        int run_start = -1;
        for (int i = 0; i <= samples; ++i) {
            bool sharp = false;
            if (i < samples) {
                const double spacing =
                    (p[std::min(i + 1, samples - 1)] - p[std::max(i - 1, 0)]).norm() / 2;
                sharp = classify_surface_point(body, p[i], spacing) != FeatureKind::smooth;
            }
            if (sharp && run_start < 0) run_start = i;
            if (!sharp && run_start >= 0) {
                // A short run crosses a crease; a long one runs along it (the half-line lies in
                // a plane of the crease, as a box's diagonal plane holds its vertical edge), and
                // its two ends are where the wall leaves it: corners.
                std::vector<std::pair<int, bool>> at = {{(run_start + i - 1) / 2, false}};
                if (i - run_start > 4) at = {{run_start, true}, {i - 1, true}};
                for (const auto& [sample, corner] : at) {
                    const double x = crease_on_half_line(body, centre, ray, dir, end, p[sample],
                                                         found.w[sample], corner, length_scale);
                    if (x > 0.05 && x < outer - 0.05) creases.push_back(x);
                }
                run_start = -1;
            }
        }
        return creases;
    };
    // Creases met within 0.03 of each other are one: from (w, half-line) pairs, the mean w of
    // each cluster and how many distinct half-lines met it.
    using Met = std::pair<double, int>;
    auto cluster = [](std::vector<Met> x, std::vector<double>& mean, std::vector<int>& count) {
        std::sort(x.begin(), x.end());
        for (size_t i = 0; i < x.size();) {
            size_t j = i + 1;
            while (j < x.size() && x[j].first - x[j - 1].first <= 0.03) ++j;
            double sum = 0;
            std::vector<int> lines;
            for (size_t k = i; k < j; ++k) sum += x[k].first, lines.push_back(x[k].second);
            std::sort(lines.begin(), lines.end());
            mean.push_back(sum / double(j - i));
            count.push_back(int(std::unique(lines.begin(), lines.end()) - lines.begin()));
            i = j;
        }
    };
    std::vector<Met> along_axes, along_diagonals;
    std::vector<Vec3> p;
    const Vec3 out[4] = {unit(b), unit(c), -unit(b), -unit(c)};
    int line = 0;
    for (const double end : {1.0, -1.0})
        for (int q = 0; q < 4; ++q, ++line) {
            for (double x : creases_along(out[q], end * unit(axis), p))
                along_axes.push_back({x, line});
            if (found.meridian.empty()) found.meridian = p;
            for (double x : creases_along(out[q] + out[(q + 1) % 4], end * unit(axis), p))
                along_diagonals.push_back({x, line});
        }
    cluster(along_axes, found.radius, found.seen);
    std::vector<double> diagonal;
    std::vector<int> diagonal_seen;
    cluster(along_diagonals, diagonal, diagonal_seen);
    // The k-th crease out along the diagonals is the k-th along the axes when they are as
    // many; otherwise each crease is taken for a circle.
    for (size_t k = 0; k < found.radius.size(); ++k)
        found.reach.push_back(diagonal.size() == found.radius.size() ? std::sqrt(2.0) * diagonal[k]
                                                                     : found.radius[k]);
    return found;
}

AxialRings fit_axial_rings(const AxialCreases& creases, int axis, int cells, double outer) {
    // Creases strictly inside (0, outer) and increasing, as find_axial_creases gives them.
    std::vector<double> rings_at, reach_at;
    for (size_t k = 0; k < creases.radius.size(); ++k) {
        const double x = creases.radius[k];
        if (x > 1e-3 * outer && x < outer * (1 - 1e-3) && (rings_at.empty() || x > rings_at.back()))
            rings_at.push_back(x), reach_at.push_back(creases.reach[k]);
    }
    if (creases.meridian.size() < 2 || creases.meridian.size() != creases.w.size())
        rings_at.clear();
    if (int(rings_at.size()) > cells - 1) {
        rings_at.resize(std::max(cells - 1, 0));
        reach_at.resize(rings_at.size());
    }
    if (rings_at.empty()) return even_axial_rings(axis, cells, outer);

    AxialRings rings;
    rings.axis = axis;
    const double column = std::min(outer / 2, rings_at.front() / 2);
    const std::vector<double>& w = creases.w;
    const std::vector<double> length = arc_lengths(creases.meridian);
    std::vector<double> stops = {column};
    stops.insert(stops.end(), rings_at.begin(), rings_at.end());
    stops.push_back(outer);
    std::vector<double> segment;
    for (size_t i = 0; i + 1 < stops.size(); ++i)
        segment.push_back(interpolate(w, length, stops[i + 1]) - interpolate(w, length, stops[i]));
    const std::vector<int> count = share_cells(segment, cells);
    rings.radius.push_back(column);
    for (size_t i = 0; i < count.size(); ++i) {
        const double from = interpolate(w, length, stops[i]);
        for (int s = 1; s <= count[i]; ++s) {
            const double at = from + segment[i] * s / count[i];
            rings.radius.push_back(s == count[i] ? stops[i + 1] : interpolate(length, w, at));
        }
    }
    // Each ring's reach along the diagonals: the creases' own, and in between it grows evenly
    // with the radius, from the column's square to the frame's.
    const double root2 = std::sqrt(2.0);
    std::vector<double> reach = {root2 * column};
    reach.insert(reach.end(), reach_at.begin(), reach_at.end());
    reach.push_back(root2 * outer);
    for (int s = 0; s <= cells; ++s) {
        const double x = rings.radius[s];
        const double d = interpolate(stops, reach, x);
        rings.roundness.push_back(std::clamp((root2 - d / x) / (root2 - 1), 0.0, 1.0));
    }
    keep_rings_nested(rings);
    return rings;
}

int choose_axis(const std::array<AxialCreases, 3>& creases) {
    int best = -1, best_count = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const AxialCreases& c = creases[axis];
        int count = 0;
        for (size_t k = 0; k < c.radius.size(); ++k)
            count += c.seen[k] >= 4 && c.reach[k] < 1.2 * c.radius[k];
        if (count > best_count) best = axis, best_count = count;
    }
    return best;
}

double axial_frame_edge(int n, int frame) {
    return frame > 0 ? equiangular_index(n - frame, n) : 1.0;
}

namespace {

using Vec2 = Eigen::Vector2d;

// One piece of the axial core's cross-section: nodes (i, j), i fastest, at in-plane cube
// coordinates (t_b, t_c), with (i, j) counter-clockwise so (i, j, axis) is right-handed.
struct SectionPiece {
    std::string name;
    int ni = 0, nj = 0;  // node counts
    std::vector<Vec2> t;
};

// The cross-section of the axial core (see axial_core): column, rings, frame.
std::vector<SectionPiece> cross_section(int n, int frame, const AxialRings& rings, int b, int c) {
    const int m = n - 2 * frame, r = rings.cells();
    const double outer = rings.radius.back();
    std::vector<SectionPiece> pieces;
    SectionPiece column{"column", m + 1, m + 1, {}};
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i)
            column.t.push_back(rings.column() *
                               Vec2(equiangular_index(i, m), equiangular_index(j, m)));
    pieces.push_back(std::move(column));
    // Piece q reaches out along d = +b, +c, -b, -c; `along` (the axis x d) turns around it.
    const Vec2 out[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const int side[4] = {2 * b + 1, 2 * c + 1, 2 * b, 2 * c};
    auto along = [&](int q) { return Vec2(-out[q].y(), out[q].x()); };
    for (int q = 0; q < 4; ++q) {
        SectionPiece ring{std::string("ring_") + cube_patches[side[q]].side, r + 1, m + 1, {}};
        for (int j = 0; j <= m; ++j)
            for (int s = 0; s <= r; ++s) {
                const double angle = pi / 4 * (2.0 * j / m - 1), round = rings.roundness[s];
                const Vec2 square = out[q] + equiangular_index(j, m) * along(q);
                const Vec2 circle = std::cos(angle) * out[q] + std::sin(angle) * along(q);
                ring.t.push_back(rings.radius[s] * ((1 - round) * square + round * circle));
            }
        pieces.push_back(std::move(ring));
    }
    if (frame == 0) return pieces;
    // The frame: its sides run from the rings' last square to the cube's faces, radially at
    // the equiangular coordinates of the cube's lattice; its corners are that lattice.
    for (int q = 0; q < 4; ++q) {
        SectionPiece f{std::string("frame_") + cube_patches[side[q]].side, frame + 1, m + 1, {}};
        const double edge = equiangular_index(n, n);
        for (int j = 0; j <= m; ++j)
            for (int i = 0; i <= frame; ++i) {
                const double radial = equiangular_index(n - frame + i, n);
                const double blend = (radial - outer) / (edge - outer);
                const Vec2 inner = outer * (out[q] + equiangular_index(j, m) * along(q));
                const Vec2 face = edge * out[q] + equiangular_index(frame + j, n) * along(q);
                f.t.push_back((1 - blend) * inner + blend * face);
            }
        pieces.push_back(std::move(f));
    }
    for (int q = 0; q < 4; ++q) {
        const int next = (q + 1) % 4;
        SectionPiece corner{std::string("frame_") + cube_patches[side[q]].side + "_" +
                                cube_patches[side[next]].side,
                            frame + 1,
                            frame + 1,
                            {}};
        for (int j = 0; j <= frame; ++j)
            for (int i = 0; i <= frame; ++i)
                corner.t.push_back(equiangular_index(n - frame + i, n) * out[q] +
                                   equiangular_index(n - frame + j, n) * out[next]);
        pieces.push_back(std::move(corner));
    }
    return pieces;
}

// Numbers the pieces' nodes once each: nodes within 1e-8 of each other (a shared edge
// computed from either side) get one id. ids[piece][node].
std::vector<std::vector<Id>> number_section(const std::vector<SectionPiece>& pieces,
                                            std::vector<Vec2>& points) {
    constexpr double quantum = 1e-8;
    std::map<std::pair<long long, long long>, Id> seen;
    std::vector<std::vector<Id>> ids;
    for (const SectionPiece& piece : pieces) {
        std::vector<Id>& piece_ids = ids.emplace_back();
        for (const Vec2& t : piece.t) {
            const long long x = std::llround(t.x() / quantum), y = std::llround(t.y() / quantum);
            Id id = -1;
            for (long long dx = -1; dx <= 1 && id < 0; ++dx)
                for (long long dy = -1; dy <= 1 && id < 0; ++dy)
                    if (auto it = seen.find({x + dx, y + dy}); it != seen.end()) id = it->second;
            if (id < 0) {
                id = Id(points.size());
                points.push_back(t);
                seen[{x, y}] = id;
            }
            piece_ids.push_back(id);
        }
    }
    return ids;
}

}  // namespace

CoreLayout axial_core(int n, int frame, const AxialRings& rings) {
    const int a = rings.axis, b = (a + 1) % 3, c = (a + 2) % 3, r = rings.cells();
    if (r < 1 || int(rings.roundness.size()) != r + 1)
        throw std::invalid_argument("axial rings: radius and roundness need cells + 1 values");
    if (frame < 0 || n - 2 * frame < 1)
        throw std::invalid_argument("axial core: the frame leaves no cells for the rings");
    if (std::abs(rings.radius.back() - axial_frame_edge(n, frame)) > 1e-12)
        throw std::invalid_argument("axial rings: the last ring is not the frame's inner edge");
    const std::vector<SectionPiece> pieces = cross_section(n, frame, rings, b, c);
    std::vector<Vec2> section;
    const std::vector<std::vector<Id>> ids = number_section(pieces, section);
    const Id per_layer = Id(section.size());

    CoreLayout core;
    core.t.resize(per_layer * (n + 1));
    for (int k = 0; k <= n; ++k)
        for (Id id = 0; id < per_layer; ++id) {
            Vec3& t = core.t[id + per_layer * k];
            t[a] = equiangular_index(k, n);
            t[b] = section[id].x();
            t[c] = section[id].y();
        }
    for (size_t p = 0; p < pieces.size(); ++p) {
        const SectionPiece& piece = pieces[p];
        Block block{"core_" + piece.name, {piece.ni, piece.nj, n + 1}, {}, {}};
        block.node_ids.resize(block.nodes.count());
        for (int k = 0; k <= n; ++k)
            for (int j = 0; j < piece.nj; ++j)
                for (int i = 0; i < piece.ni; ++i)
                    block.node_ids[block.nodes.flat(i, j, k)] =
                        ids[p][i + piece.ni * j] + per_layer * k;
        // Faces on the cube's sides: every node of the piece's edge at |t_b| or |t_c| = 1.
        for (const BlockFace face : {imin, imax, jmin, jmax}) {
            for (const int d : {b, c}) {
                const Id first =
                    block.node(face == imax ? piece.ni - 1 : 0, face == jmax ? piece.nj - 1 : 0, 0);
                const double sign = core.t[first][d] > 0 ? 1.0 : -1.0;
                bool on_side = true;
                const int count = face < jmin ? piece.nj : piece.ni;
                for (int e = 0; e < count && on_side; ++e) {
                    const int i = face < jmin ? (face == imax ? piece.ni - 1 : 0) : e;
                    const int j = face < jmin ? e : (face == jmax ? piece.nj - 1 : 0);
                    on_side = sign * core.t[block.node(i, j, 0)][d] > 1 - 1e-9;
                }
                if (on_side) core.wall_faces.push_back({int(p), face, 2 * d + (sign > 0)});
            }
        }
        core.wall_faces.push_back({int(p), kmin, 2 * a});
        core.wall_faces.push_back({int(p), kmax, 2 * a + 1});
        core.blocks.push_back(std::move(block));
    }
    return core;
}

}  // namespace hexmesh

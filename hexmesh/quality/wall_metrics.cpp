#include "hexmesh/quality/wall_metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "hexmesh/core/bytes.h"
#include "surface/exact_distance.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double inf = std::numeric_limits<double>::infinity();

// What one wall-normal line contributes.
struct LineMeasures {
    Vec3 first_edge = Vec3::Zero();  // x1 - x0
    // The unit wall normals at x0 (into the grid): n, and at a crease or corner node the
    // normals of the other smooth pieces meeting there (up to 3 in all).
    std::array<Vec3, 3> normals;
    int normal_count = 0;
    double angle_deg = 0;  // between x1 - x0 and n
    Id ratios = 0, ratios_within = 0;
    double ratio_min = inf, ratio_max = -inf, ratio_sum = 0;
};

// Its growth ratios also go into `ratio_bins` (over growth_target when there is one).
LineMeasures measure_line(const WallFace& f, int p, int q, const std::vector<Vec3>& points,
                          const ImplicitFunction& body, double side, int ratios,
                          double growth_target, Histogram& ratio_bins) {
    LineMeasures m;
    const Vec3 x0 = points[f.node(p, q, 0)];
    const Vec3 edge = points[f.node(p, q, 1)] - x0;
    const Vec3 g = body.gradient(x0);
    const double g_norm = g.norm();
    const Vec3 n =
        g_norm > 0 && std::isfinite(g_norm) ? Vec3(side * g / g_norm) : Vec3(edge.normalized());
    m.first_edge = edge;
    m.normals[m.normal_count++] = n;
    // The pieces active within 1e-3 of the shortest wall edge at x0 (the wall spacing, which
    // feature snapping places crease nodes well within; the first edge can be far thinner).
    double spacing_along_wall = inf;
    for (const auto& [dp, dq] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
        if (p + dp >= 0 && p + dp < f.np && q + dq >= 0 && q + dq < f.nq)
            spacing_along_wall =
                std::min(spacing_along_wall, (points[f.node(p + dp, q + dq, 0)] - x0).norm());
    if (!std::isfinite(spacing_along_wall)) spacing_along_wall = edge.norm();
    std::vector<Vec3> normals = {n};
    append_wall_normals(body, x0, side, 1e-3 * spacing_along_wall, normals);
    for (size_t i = 1; i < normals.size() && m.normal_count < int(m.normals.size()); ++i)
        m.normals[m.normal_count++] = normals[i];
    // At a crease or corner the angle is taken from the bisector of the faces meeting there
    // (the direction of unit_offset), the best a line leaving it can do; elsewhere from n.
    const std::optional<Vec3> offset =
        m.normal_count > 1 ? unit_offset(body, x0, side, 1e-3 * spacing_along_wall) : std::nullopt;
    const Vec3 ideal = offset ? Vec3(offset->normalized()) : n;
    m.angle_deg = std::atan2(edge.cross(ideal).norm(), edge.dot(ideal)) * 180 / pi;

    double spacing = edge.norm();
    for (int e = 1; e <= ratios; ++e) {
        const double next = (points[f.node(p, q, e + 1)] - points[f.node(p, q, e)]).norm();
        const double r = next / spacing;
        ++m.ratios;
        m.ratios_within += growth_target > 0 && std::abs(r - growth_target) <= 0.05 * growth_target;
        m.ratio_min = std::min(m.ratio_min, r);
        m.ratio_max = std::max(m.ratio_max, r);
        m.ratio_sum += r;
        ratio_bins.add(growth_target > 0 ? r / growth_target : r);
        spacing = next;
    }
    return m;
}

// The first-layer thickness of the wall cell (p, q) of `f`: the mean over its 4 wall nodes of
// (x1 - x0) . n, n the node's wall normal; at a crease or corner node, the normal of the
// piece the cell lies on: the one nearest the normal of the cell's wall face (the cross
// product of its diagonals). The line there leaves along the bisector of the pieces, at the
// law's height above each of them.
double cell_thickness(const WallFace& f, int p, int q, const std::vector<Vec3>& points,
                      const std::vector<LineMeasures>& lines) {
    const Vec3 a = points[f.node(p, q, 0)], b = points[f.node(p + 1, q, 0)],
               c = points[f.node(p + 1, q + 1, 0)], d = points[f.node(p, q + 1, 0)];
    const Vec3 face = (c - a).cross(d - b);  // either orientation: nearest up to sign
    double sum = 0;
    for (const auto& [s, t] : {std::pair{p, q}, {p + 1, q}, {p, q + 1}, {p + 1, q + 1}}) {
        const LineMeasures& m = lines[s + Id(f.np) * t];
        const Vec3* n = &m.normals[0];
        for (int i = 1; i < m.normal_count; ++i)
            if (std::abs(m.normals[i].dot(face)) > std::abs(n->dot(face))) n = &m.normals[i];
        sum += m.first_edge.dot(*n);
    }
    return 0.25 * sum;
}

}  // namespace

WallMeter::WallMeter(const ImplicitFunction& body, const WallLayers& law) : body_(body), law_(law) {
    w_.first_layer_target = law.layers > 0 ? law.first_height : 0;
    w_.growth_ratio_target = law.layers > 1 ? law.growth_ratio : 0;
    w_.first_layer_histogram = Histogram(0, 2, 20);
    w_.growth_ratio_histogram =
        w_.growth_ratio_target > 0 ? Histogram(0.8, 1.2, 20) : Histogram(0.5, 2.5, 20);
    w_.first_layer_min = w_.growth_ratio_min = inf;
    w_.first_layer_max = w_.growth_ratio_max = -inf;
}

void WallMeter::add(const BlockGrid& grid, const Block& block,
                    const std::array<bool, 3>& skip_first) {
    WallQuality& w = w_;
    for (const WallFace& f : wall_faces(block)) {
        // The lines another part of the same block measures too (see wall_metrics.h).
        const auto skipped = [&](Id l) {
            return (skip_first[size_t(f.axis_p)] && l % f.np == 0) ||
                   (skip_first[size_t(f.axis_q)] && l / f.np == 0);
        };
        const double side = grid_side(f, grid.points, body_);
        // Ratios m = 0 .. ratios-1 compare edges m and m+1 of the line.
        const int edges = f.depth - 1;
        const int ratios =
            std::max(0, law_.layers > 0 ? std::min(law_.layers, edges) - 1 : edges - 1);
        std::vector<LineMeasures> lines(f.lines());
        // The ratios' bins per thread (counts: the order does not matter).
        tbb::enumerable_thread_specific<Histogram> ratio_bins(
            [&] { return w.growth_ratio_histogram.empty_copy(); });
        tbb::enumerable_thread_specific<Histogram> ignored(
            [&] { return w.growth_ratio_histogram.empty_copy(); });
        tbb::parallel_for(Id(0), f.lines(), [&](Id l) {
            lines[l] = measure_line(f, int(l % f.np), int(l / f.np), grid.points, body_, side,
                                    ratios, w.growth_ratio_target,
                                    skipped(l) ? ignored.local() : ratio_bins.local());
        });
        for (const Histogram& local : ratio_bins) w.growth_ratio_histogram.join(local);

        // Reduced in a fixed order, so the sums do not depend on the thread count.
        for (Id l = 0; l < f.lines(); ++l) {
            if (skipped(l)) continue;
            const LineMeasures& m = lines[size_t(l)];
            w.orthogonality_max_deg = std::max(w.orthogonality_max_deg, m.angle_deg);
            angle_sum_ += m.angle_deg;
            ++angles_;
            w.growth_ratios += m.ratios;
            ratios_within_ += m.ratios_within;
            w.growth_ratio_min = std::min(w.growth_ratio_min, m.ratio_min);
            w.growth_ratio_max = std::max(w.growth_ratio_max, m.ratio_max);
            ratio_sum_ += m.ratio_sum;
        }
        for (int q = 0; q + 1 < f.nq; ++q)
            for (int p = 0; p + 1 < f.np; ++p) {
                const double t = cell_thickness(f, p, q, grid.points, lines);
                ++w.wall_cells;
                thickness_sum_ += t;
                if (t < w.first_layer_min) {
                    w.first_layer_min = t;
                    w.first_layer_min_at =
                        (grid.points[f.node(p, q, 0)] + grid.points[f.node(p + 1, q, 0)] +
                         grid.points[f.node(p + 1, q + 1, 0)] + grid.points[f.node(p, q + 1, 0)]) /
                        4;
                }
                w.cells_through_wall += !(t > 0);
                w.first_layer_max = std::max(w.first_layer_max, t);
                thickness_within_ +=
                    w.first_layer_target > 0 &&
                    std::abs(t - w.first_layer_target) <= 0.1 * w.first_layer_target;
                if (w.first_layer_target > 0) w.first_layer_histogram.add(t / w.first_layer_target);
            }
    }
}

WallQuality WallMeter::result() const {
    WallQuality w = w_;
    if (w.wall_cells > 0) {
        w.first_layer_mean = thickness_sum_ / w.wall_cells;
        w.first_layer_within_10_percent = double(thickness_within_) / w.wall_cells;
    } else {
        w.first_layer_min = w.first_layer_max = 0;
    }
    if (angles_ > 0) w.orthogonality_mean_deg = angle_sum_ / angles_;
    if (w.growth_ratios > 0) {
        w.growth_ratio_mean = ratio_sum_ / w.growth_ratios;
        w.growth_ratio_within_5_percent = double(ratios_within_) / w.growth_ratios;
    } else {
        w.growth_ratio_min = w.growth_ratio_max = 0;
    }
    return w;
}

std::string WallMeter::pack() const {
    ByteWriter out;
    const WallQuality& w = w_;
    out.put(w.wall_cells), out.put(w.first_layer_min), out.put(w.first_layer_max);
    out.put(w.growth_ratios), out.put(w.growth_ratio_min), out.put(w.growth_ratio_max);
    out.put(w.orthogonality_max_deg);
    out.put(w.first_layer_histogram), out.put(w.growth_ratio_histogram);
    out.put(thickness_sum_), out.put(angle_sum_), out.put(ratio_sum_);
    out.put(thickness_within_), out.put(angles_), out.put(ratios_within_);
    out.put(w.cells_through_wall), out.put(w.first_layer_min_at);
    return out.bytes();
}

void WallMeter::merge(const std::string& packed) {
    ByteReader in(packed);
    WallQuality& w = w_;
    w.wall_cells += in.next<Id>();
    const double thinnest = in.next<double>();
    w.first_layer_max = std::max(w.first_layer_max, in.next<double>());
    w.growth_ratios += in.next<Id>();
    w.growth_ratio_min = std::min(w.growth_ratio_min, in.next<double>());
    w.growth_ratio_max = std::max(w.growth_ratio_max, in.next<double>());
    w.orthogonality_max_deg = std::max(w.orthogonality_max_deg, in.next<double>());
    w.first_layer_histogram.join(in.next<Histogram>());
    w.growth_ratio_histogram.join(in.next<Histogram>());
    thickness_sum_ += in.next<double>();
    angle_sum_ += in.next<double>();
    ratio_sum_ += in.next<double>();
    thickness_within_ += in.next<Id>();
    angles_ += in.next<Id>();
    ratios_within_ += in.next<Id>();
    w.cells_through_wall += in.next<Id>();
    const Vec3 thinnest_at = in.next<Vec3>();
    if (thinnest < w.first_layer_min)
        w.first_layer_min = thinnest, w.first_layer_min_at = thinnest_at;
}

WallQuality measure_wall(const BlockGrid& grid, const ImplicitFunction& body,
                         const WallLayers& law) {
    WallMeter meter(body, law);
    for (const Block& block : grid.blocks) meter.add(grid, block);
    return meter.result();
}

void append_wall_triangles(const BlockGrid& grid, const Block& block, TriangleSurface& wall) {
    std::unordered_map<Id, int> local;  // the block's wall nodes in `wall`
    auto local_id = [&](Id v) {
        const auto [it, inserted] = local.try_emplace(v, int(wall.points.size()));
        if (inserted) {
            if (wall.points.size() >= size_t(std::numeric_limits<int>::max()))
                throw std::invalid_argument("hausdorff_to_surface: too many wall nodes");
            wall.points.push_back(grid.points[v]);
        }
        return it->second;
    };
    for (const WallFace& f : wall_faces(block))
        for (int q = 0; q + 1 < f.nq; ++q)
            for (int p = 0; p + 1 < f.np; ++p) {
                const int a = local_id(f.node(p, q, 0)), b = local_id(f.node(p + 1, q, 0)),
                          c = local_id(f.node(p + 1, q + 1, 0)), d = local_id(f.node(p, q + 1, 0));
                wall.triangles.push_back({a, b, c});
                wall.triangles.push_back({a, c, d});
            }
}

namespace {

// The grid's wall faces as triangles (append_wall_triangles over every block); throws when
// there is none.
TriangleSurface wall_triangles(const BlockGrid& grid, const char* caller) {
    TriangleSurface wall;
    for (const Block& block : grid.blocks) append_wall_triangles(grid, block, wall);
    if (wall.triangles.empty())
        throw std::invalid_argument(std::string(caller) + ": the grid has no wall face");
    return wall;
}

// The vertices the surface's triangles use.
std::vector<Vec3> used_vertices(const TriangleSurface& surface) {
    std::vector<char> used(surface.points.size(), 0);
    for (const auto& t : surface.triangles)
        for (int v : t) used[v] = 1;
    std::vector<Vec3> vertices;
    for (size_t v = 0; v < surface.points.size(); ++v)
        if (used[v]) vertices.push_back(surface.points[v]);
    return vertices;
}

// d's surface_in_cells_* of the first `vertices` samples against the size of the wall quad
// nearest to each.
void measure_in_cells(const TriangleSurface& wall, const ExactDistance& to_wall,
                      const std::vector<Vec3>& samples, size_t vertices, HausdorffDistance& d) {
    std::vector<double> in_cells(vertices);
    const auto area = [&](size_t t) {
        const auto& tri = wall.triangles[t];
        return 0.5 * (wall.points[tri[1]] - wall.points[tri[0]])
                         .cross(wall.points[tri[2]] - wall.points[tri[0]])
                         .norm();
    };
    tbb::parallel_for(size_t(0), vertices, [&](size_t v) {
        const size_t quad = size_t(to_wall.closest_triangle(samples[v])) / 2;
        const double size = std::sqrt(area(2 * quad) + area(2 * quad + 1));
        in_cells[v] = to_wall.distance(samples[v]) / std::max(size, 1e-300);
    });
    if (!in_cells.empty()) {
        const size_t worst =
            size_t(std::max_element(in_cells.begin(), in_cells.end()) - in_cells.begin());
        d.surface_in_cells_at = samples[worst];
        d.surface_in_cells_distance = to_wall.distance(samples[worst]);
        std::sort(in_cells.begin(), in_cells.end());
        d.surface_in_cells_max = in_cells.back();
        // Nearest rank: the smallest value at or above 99 % of the vertices.
        const size_t rank = size_t(std::ceil(0.99 * double(in_cells.size())));
        d.surface_in_cells_p99 = in_cells[std::clamp<size_t>(rank, 1, in_cells.size()) - 1];
    }
}

}  // namespace

HausdorffDistance hausdorff_to_surface(const TriangleSurface& wall,
                                       const TriangleSurface& surface) {
    if (wall.triangles.empty())
        throw std::invalid_argument("hausdorff_to_surface: the grid has no wall face");

    // Surface samples: the vertices the triangles use, then the centroids.
    std::vector<Vec3> samples = used_vertices(surface);
    const size_t vertices = samples.size();
    for (const auto& t : surface.triangles)
        samples.push_back((surface.points[t[0]] + surface.points[t[1]] + surface.points[t[2]]) / 3);

    HausdorffDistance d;
    d.grid_to_surface = max_distance_to(ExactDistance(surface), wall.points);
    const ExactDistance to_wall(wall);
    d.surface_to_grid = max_distance_to(to_wall, samples);
    d.hausdorff = std::max(d.grid_to_surface, d.surface_to_grid);
    measure_in_cells(wall, to_wall, samples, vertices, d);
    return d;
}

HausdorffDistance hausdorff_to_surface(const BlockGrid& grid, const TriangleSurface& surface) {
    return hausdorff_to_surface(wall_triangles(grid, "hausdorff_to_surface"), surface);
}

HausdorffDistance surface_to_wall_in_cells(const BlockGrid& grid, const TriangleSurface& surface) {
    const TriangleSurface wall = wall_triangles(grid, "surface_to_wall_in_cells");
    const std::vector<Vec3> vertices = used_vertices(surface);
    HausdorffDistance d;
    measure_in_cells(wall, ExactDistance(wall), vertices, vertices.size(), d);
    return d;
}

}  // namespace hexmesh

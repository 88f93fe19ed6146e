#include "surface/cross_sections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hexmesh {

using Vec2 = Eigen::Vector2d;

double section_distance(const Section& section, const Vec2& q, Vec2* gradient) {
    double best = std::numeric_limits<double>::infinity();
    Vec2 closest = q, edge_normal = Vec2::UnitX();
    bool inside = false;
    for (const auto& loop : section.loops) {
        for (size_t i = 0, n = loop.size(); i < n; ++i) {
            const Vec2 &a = loop[i], &b = loop[(i + 1) % n];
            const Vec2 ab = b - a;
            const double length2 = ab.squaredNorm();
            const double t = length2 > 0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
            const Vec2 c = a + t * ab;
            const double d2 = (q - c).squaredNorm();
            if (d2 < best) best = d2, closest = c, edge_normal = Vec2(ab.y(), -ab.x());
            // Even-odd rule: a ray from q towards +x crosses the edge.
            if ((a.y() > q.y()) != (b.y() > q.y()) &&
                q.x() < a.x() + (q.y() - a.y()) * ab.x() / ab.y())
                inside = !inside;
        }
    }
    const double sign = inside ? -1.0 : 1.0;
    const double d = std::sqrt(best);
    if (gradient) {
        if (d > 0) {
            *gradient = sign * (q - closest) / d;
        } else {  // on an edge: its normal, whichever way the loop runs
            const double length = edge_normal.norm();
            *gradient = length > 0 ? Vec2(edge_normal / length) : Vec2(Vec2::UnitX());
        }
    }
    return sign * d;
}

CrossSectionSdf::CrossSectionSdf(SectionStack stack) : stack_(std::move(stack)) {
    const auto& sections = stack_.sections;
    if (sections.size() < 2)
        throw std::invalid_argument("CrossSectionSdf: needs at least 2 sections, got " +
                                    std::to_string(sections.size()));
    bounds_.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    bounds_.hi = -bounds_.lo;
    for (size_t k = 0; k < sections.size(); ++k) {
        const Section& s = sections[k];
        if (!std::isfinite(s.z) || (k > 0 && !(s.z > sections[k - 1].z)))
            throw std::invalid_argument(
                "CrossSectionSdf: section z must be finite and strictly "
                "increasing (section " +
                std::to_string(k) + ")");
        if (s.loops.empty())
            throw std::invalid_argument("CrossSectionSdf: section " + std::to_string(k) +
                                        " has no polyline");
        for (const auto& loop : s.loops) {
            if (loop.size() < 3)
                throw std::invalid_argument("CrossSectionSdf: a polyline of section " +
                                            std::to_string(k) + " has fewer than 3 points");
            for (const Vec2& p : loop) {
                if (!p.allFinite())
                    throw std::invalid_argument("CrossSectionSdf: non-finite point in section " +
                                                std::to_string(k));
                bounds_.lo.head<2>() = bounds_.lo.head<2>().cwiseMin(p);
                bounds_.hi.head<2>() = bounds_.hi.head<2>().cwiseMax(p);
            }
        }
    }
    bounds_.lo.z() = sections.front().z;
    bounds_.hi.z() = sections.back().z;
}

ImplicitFunction::Piece CrossSectionSdf::side(const Vec3& p) const {
    const auto& sections = stack_.sections;
    const Vec2 q = p.head<2>();
    Vec2 g0, g1;
    if (p.z() <= sections.front().z || p.z() >= sections.back().z) {
        const Section& end = p.z() <= sections.front().z ? sections.front() : sections.back();
        const double d = section_distance(end, q, &g0);
        return {d, Vec3(g0.x(), g0.y(), 0)};
    }
    // sections[k].z <= z < sections[k + 1].z
    const auto above = std::upper_bound(sections.begin(), sections.end(), p.z(),
                                        [](double z, const Section& s) { return z < s.z; });
    const Section &s1 = *above, &s0 = *(above - 1);
    const double dz = s1.z - s0.z, t = (p.z() - s0.z) / dz;
    const double d0 = section_distance(s0, q, &g0), d1 = section_distance(s1, q, &g1);
    const Vec2 gxy = (1 - t) * g0 + t * g1;
    return {(1 - t) * d0 + t * d1, Vec3(gxy.x(), gxy.y(), (d1 - d0) / dz)};
}

double CrossSectionSdf::value(const Vec3& p) const {
    const double s = side(p).value;
    const double cap = std::max(p.z() - bounds_.hi.z(), bounds_.lo.z() - p.z());
    if (s > 0 && cap > 0) return std::hypot(s, cap);
    return std::max(s, cap);
}

Vec3 CrossSectionSdf::gradient(const Vec3& p) const {
    const Piece s = side(p);
    const bool top = p.z() - bounds_.hi.z() > bounds_.lo.z() - p.z();
    const double cap = top ? p.z() - bounds_.hi.z() : bounds_.lo.z() - p.z();
    const Vec3 cap_gradient(0, 0, top ? 1.0 : -1.0);
    if (s.value > 0 && cap > 0) {
        const double u = std::hypot(s.value, cap);
        return (s.value * s.gradient + cap * cap_gradient) / u;
    }
    return s.value >= cap ? s.gradient : cap_gradient;
}

void CrossSectionSdf::active_pieces(const Vec3& p, double tolerance,
                                    std::vector<Piece>& out) const {
    const Piece pieces[3] = {
        side(p), {p.z() - bounds_.hi.z(), Vec3::UnitZ()}, {bounds_.lo.z() - p.z(), -Vec3::UnitZ()}};
    const double largest = std::max({pieces[0].value, pieces[1].value, pieces[2].value});
    for (const Piece& piece : pieces)
        if (piece.value >= largest - std::max(tolerance, 0.0)) out.push_back(piece);
}

Box3 CrossSectionSdf::bounds() const {
    return bounds_;
}

namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

CGAL::Polygon_2<Epick> polygon_of(const std::vector<Eigen::Vector2d>& loop) {
    CGAL::Polygon_2<Epick> polygon;
    for (const Eigen::Vector2d& q : loop) polygon.push_back(Epick::Point_2(q.x(), q.y()));
    return polygon;
}

// Whether the closed polylines a and b cross or touch (exact segment tests after a box test).
bool loops_cross(const CGAL::Polygon_2<Epick>& a, const CGAL::Polygon_2<Epick>& b) {
    if (!CGAL::do_overlap(a.bbox(), b.bbox())) return false;
    for (auto ea = a.edges_begin(); ea != a.edges_end(); ++ea) {
        if (!CGAL::do_overlap(ea->bbox(), b.bbox())) continue;
        for (auto eb = b.edges_begin(); eb != b.edges_end(); ++eb)
            if (CGAL::do_intersect(*ea, *eb)) return true;
    }
    return false;
}

}  // namespace

SectionDiagnostics diagnose_sections(const SectionStack& stack) {
    SectionDiagnostics d;
    d.sections = (long long)stack.sections.size();
    bool first = true;
    d.smallest_loop_area = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < stack.sections.size(); ++s) {
        const Section& section = stack.sections[s];
        if (s > 0) {
            const double gap = section.z - stack.sections[s - 1].z;
            d.min_spacing = s == 1 ? gap : std::min(d.min_spacing, gap);
            d.max_spacing = std::max(d.max_spacing, gap);
        }
        std::vector<CGAL::Polygon_2<Epick>> polygons;
        for (const auto& loop : section.loops) {
            ++d.loops;
            d.points += (long long)loop.size();
            for (const Eigen::Vector2d& q : loop) {
                const Vec3 p(q.x(), q.y(), section.z);
                d.bounds.lo = first ? p : Vec3(d.bounds.lo.cwiseMin(p));
                d.bounds.hi = first ? p : Vec3(d.bounds.hi.cwiseMax(p));
                first = false;
            }
            polygons.push_back(polygon_of(loop));
            d.smallest_loop_area = std::min(d.smallest_loop_area, std::abs(polygons.back().area()));
            d.self_intersecting_loops += !polygons.back().is_simple();
        }
        for (size_t a = 0; a < polygons.size(); ++a)
            for (size_t b = a + 1; b < polygons.size(); ++b)
                d.crossing_loops += loops_cross(polygons[a], polygons[b]);
    }
    if (d.loops == 0) d.smallest_loop_area = 0;
    return d;
}

}  // namespace hexmesh

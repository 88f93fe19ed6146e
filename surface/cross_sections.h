// Implicit body from a stack of planar cross-sections perpendicular to z.
#pragma once

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/point_samples.h"

namespace hexmesh {

// In each section, d_k(x, y): the 2D signed distance to its closed polylines (negative
// inside by the even-odd rule). Between the sections k and k+1 around z the side is
//   s(x) = (1 - t) d_k(x, y) + t d_{k+1}(x, y),  t = (z - z_k) / (z_{k+1} - z_k),
// below the bottom section s = d_bottom, above the top s = d_top. The body is capped by
// the planes of the end sections: pieces s, z - z_top and z_bottom - z, and
//   u = max(s, z - z_top, z_bottom - z)
// wherever at most one of them is positive; outside a rim, where s and a cap are both
// positive, u = sqrt(s^2 + cap^2), the distance to the rim for a prism (as for the analytic
// Cylinder). s is a true distance in each section and for prisms (sections of equal
// shape); between changing sections it is an interpolation (|grad u| != 1 for a cone).
// value() costs O(points of two sections); thread safe.
class CrossSectionSdf : public ImplicitFunction {
  public:
    // Throws std::invalid_argument for fewer than 2 sections, z not strictly increasing,
    // a section without polyline, a polyline with fewer than 3 points, or a non-finite
    // number.
    explicit CrossSectionSdf(SectionStack stack);

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    // The side piece and the caps within `tolerance` of their max (a crease at a rim).
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;  // the sections' xy box from the bottom to the top z

    const SectionStack& stack() const { return stack_; }

  private:
    // The side piece s at p and its gradient.
    Piece side(const Vec3& p) const;

    SectionStack stack_;
    Box3 bounds_;
};

// The 2D signed distance from q to the closed polylines of `section` (negative inside by
// the even-odd rule), and its gradient in `gradient` when not null.
double section_distance(const Section& section, const Eigen::Vector2d& q,
                        Eigen::Vector2d* gradient = nullptr);

// Health report of a cross-section stack, for `hexmesh inspect`.
struct SectionDiagnostics {
    long long sections = 0, loops = 0, points = 0;
    Box3 bounds;                              // the sections' xy box from bottom to top z
    double min_spacing = 0, max_spacing = 0;  // between consecutive sections along z
    double smallest_loop_area = 0;            // |area| of the smallest polyline
    long long self_intersecting_loops = 0;    // polylines crossing themselves (not simple)
    long long crossing_loops = 0;             // pairs of polylines of a section that cross
};

// Simplicity and crossings with CGAL's exact predicates. Expects what read_sections
// returns (at least 3 points per polyline).
SectionDiagnostics diagnose_sections(const SectionStack& stack);

}  // namespace hexmesh

#include "surface/analytic.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace hexmesh {

namespace {

using Vec2 = Eigen::Vector2d;
using Piece = ImplicitFunction::Piece;

// Appends the pieces of a max combination whose value is within tolerance of the largest.
void add_pieces_near_max(const Piece* pieces, int count, double tolerance,
                         std::vector<Piece>& out) {
    double largest = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < count; ++i) largest = std::max(largest, pieces[i].value);
    const double floor = largest - std::max(tolerance, 0.0);
    for (int i = 0; i < count; ++i)
        if (pieces[i].value >= floor) out.push_back(pieces[i]);
}

void require_positive(double x, const char* what) {
    if (!(x > 0) || !std::isfinite(x))
        throw std::invalid_argument(std::string(what) + " must be a positive finite number, got " +
                                    std::to_string(x));
}

// Unit radial direction in the xy plane of the offset d; +x on the axis.
Vec3 radial_direction(const Vec3& d) {
    const double rho = std::hypot(d.x(), d.y());
    if (rho == 0) return Vec3::UnitX();
    return Vec3(d.x() / rho, d.y() / rho, 0);
}

// Signed distance to the 2D box |q_i| <= h_i, given q = |x| - h componentwise.
double box_distance(const Vec2& q) {
    const double outside = q.cwiseMax(0.0).norm();
    return outside > 0 ? outside : q.maxCoeff();
}

// Gradient of box_distance with respect to q (q lives in the positive quadrant frame).
Vec2 box_distance_gradient(const Vec2& q) {
    const Vec2 qp = q.cwiseMax(0.0);
    const double outside = qp.norm();
    if (outside > 0) return qp / outside;
    return q[0] >= q[1] ? Vec2(1, 0) : Vec2(0, 1);
}

// Map a gradient in the meridian half plane (rho, z) to 3D.
Vec3 from_meridian(const Vec3& d, const Vec2& g) {
    return g[0] * radial_direction(d) + g[1] * Vec3::UnitZ();
}

}  // namespace

// ---------------------------------------------------------------- Sphere

Sphere::Sphere(const Vec3& center, double radius) : center_(center), radius_(radius) {
    require_positive(radius, "Sphere radius");
}

double Sphere::value(const Vec3& p) const {
    return (p - center_).norm() - radius_;
}

Vec3 Sphere::gradient(const Vec3& p) const {
    const Vec3 d = p - center_;
    const double n = d.norm();
    return n > 0 ? Vec3(d / n) : Vec3::UnitZ();
}

Box3 Sphere::bounds() const {
    const Vec3 r = Vec3::Constant(radius_);
    return {center_ - r, center_ + r};
}

// ---------------------------------------------------------------- Ellipsoid

Ellipsoid::Ellipsoid(const Vec3& center, const Vec3& semi_axes)
    : center_(center), semi_axes_(semi_axes) {
    for (int a = 0; a < 3; ++a) require_positive(semi_axes[a], "Ellipsoid semi-axis");
}

double Ellipsoid::value(const Vec3& p) const {
    const Vec3 d = p - center_;
    const Vec3 s = d.cwiseQuotient(semi_axes_);                // x_i / a_i
    const double r = s.norm();                                 // g + 1
    const double grad_r = s.cwiseQuotient(semi_axes_).norm();  // |grad g| * r
    if (grad_r == 0) return -semi_axes_.minCoeff();
    return (r - 1) * r / grad_r;
}

Box3 Ellipsoid::bounds() const {
    return {center_ - semi_axes_, center_ + semi_axes_};
}

// ---------------------------------------------------------------- Box

Box::Box(const Vec3& center, const Vec3& half_sizes) : center_(center), half_sizes_(half_sizes) {
    for (int a = 0; a < 3; ++a) require_positive(half_sizes[a], "Box half size");
}

double Box::value(const Vec3& p) const {
    const Vec3 q = (p - center_).cwiseAbs() - half_sizes_;
    const double outside = q.cwiseMax(0.0).norm();
    return outside > 0 ? outside : q.maxCoeff();
}

Vec3 Box::gradient(const Vec3& p) const {
    const Vec3 d = p - center_;
    const Vec3 q = d.cwiseAbs() - half_sizes_;
    const Vec3 sign(d.x() < 0 ? -1.0 : 1.0, d.y() < 0 ? -1.0 : 1.0, d.z() < 0 ? -1.0 : 1.0);
    const Vec3 qp = q.cwiseMax(0.0);
    const double outside = qp.norm();
    if (outside > 0) return (qp / outside).cwiseProduct(sign);
    int axis = 0;
    q.maxCoeff(&axis);
    Vec3 g = Vec3::Zero();
    g[axis] = sign[axis];
    return g;
}

void Box::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const Vec3 d = p - center_;
    Piece faces[3];
    for (int a = 0; a < 3; ++a)
        faces[a] = {std::abs(d[a]) - half_sizes_[a], (d[a] < 0 ? -1.0 : 1.0) * Vec3::Unit(a)};
    add_pieces_near_max(faces, 3, tolerance, out);
}

Box3 Box::bounds() const {
    return {center_ - half_sizes_, center_ + half_sizes_};
}

// ---------------------------------------------------------------- Cylinder

Cylinder::Cylinder(const Vec3& center, double radius, double half_height)
    : center_(center), radius_(radius), half_height_(half_height) {
    require_positive(radius, "Cylinder radius");
    require_positive(half_height, "Cylinder half height");
}

double Cylinder::value(const Vec3& p) const {
    const Vec3 d = p - center_;
    return box_distance(Vec2(std::hypot(d.x(), d.y()) - radius_, std::abs(d.z()) - half_height_));
}

Vec3 Cylinder::gradient(const Vec3& p) const {
    const Vec3 d = p - center_;
    Vec2 g = box_distance_gradient(
        Vec2(std::hypot(d.x(), d.y()) - radius_, std::abs(d.z()) - half_height_));
    if (d.z() < 0) g[1] = -g[1];
    return from_meridian(d, g);
}

void Cylinder::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const Vec3 d = p - center_;
    const Piece pieces[2] = {{std::hypot(d.x(), d.y()) - radius_, radial_direction(d)},
                             {std::abs(d.z()) - half_height_, Vec3(0, 0, d.z() < 0 ? -1.0 : 1.0)}};
    add_pieces_near_max(pieces, 2, tolerance, out);
}

Box3 Cylinder::bounds() const {
    const Vec3 h(radius_, radius_, half_height_);
    return {center_ - h, center_ + h};
}

// ---------------------------------------------------------------- Torus

Torus::Torus(const Vec3& center, double major_radius, double minor_radius)
    : center_(center), major_radius_(major_radius), minor_radius_(minor_radius) {
    require_positive(major_radius, "Torus major radius");
    require_positive(minor_radius, "Torus minor radius");
    if (minor_radius >= major_radius)
        throw std::invalid_argument("Torus minor radius (" + std::to_string(minor_radius) +
                                    ") must be smaller than the major radius (" +
                                    std::to_string(major_radius) + ")");
}

double Torus::value(const Vec3& p) const {
    const Vec3 d = p - center_;
    return std::hypot(std::hypot(d.x(), d.y()) - major_radius_, d.z()) - minor_radius_;
}

Vec3 Torus::gradient(const Vec3& p) const {
    const Vec3 d = p - center_;
    const Vec2 q(std::hypot(d.x(), d.y()) - major_radius_, d.z());
    const double n = q.norm();
    return from_meridian(d, n > 0 ? Vec2(q / n) : Vec2(0, 1));
}

Box3 Torus::bounds() const {
    const double r = major_radius_ + minor_radius_;
    const Vec3 h(r, r, minor_radius_);
    return {center_ - h, center_ + h};
}

// ---------------------------------------------------------------- Cone

namespace {

struct MeridianDistance {
    double value;   // signed distance to the trapezoid
    Vec2 gradient;  // d value / d (rho, z), unit
};

// Signed distance from q = (rho >= 0, z) to the trapezoid with corners (0, -h), (r0, -h),
// (r1, h), (0, h). The segment on the axis is not boundary (the solid is its revolution),
// and for rho >= 0 the mirrored half is never closer, so three segments suffice.
MeridianDistance cone_meridian(const Vec2& q, double r0, double r1, double h) {
    const Vec2 corners[4] = {{0, -h}, {r0, -h}, {r1, h}, {0, h}};
    const double slant_length = std::hypot(r1 - r0, 2 * h);
    const Vec2 normals[3] = {{0, -1}, Vec2(2 * h, r0 - r1) / slant_length, {0, 1}};

    double best = std::numeric_limits<double>::infinity();
    Vec2 nearest = corners[0];
    int best_segment = 0;
    for (int s = 0; s < 3; ++s) {
        const Vec2 a = corners[s];
        const Vec2 e = corners[s + 1] - a;
        const double len2 = e.squaredNorm();
        const double t = len2 > 0 ? std::clamp((q - a).dot(e) / len2, 0.0, 1.0) : 0.0;
        const Vec2 c = a + t * e;
        const double dist = (q - c).norm();
        if (dist < best) {
            best = dist;
            nearest = c;
            best_segment = s;
        }
    }

    const double radius_at_z = r0 + (r1 - r0) * (q[1] + h) / (2 * h);
    const bool inside = std::abs(q[1]) <= h && q[0] <= radius_at_z;
    const double sign = inside ? -1.0 : 1.0;
    // Near the boundary the direction to the nearest point is rounding noise: use the
    // active segment's outward normal instead.
    const double tiny = 1e-12 * std::max({r0, r1, h});
    Vec2 g = best > tiny ? Vec2(sign * (q - nearest) / best) : normals[best_segment];
    return {sign * best, g};
}

}  // namespace

Cone::Cone(const Vec3& center, double bottom_radius, double top_radius, double half_height)
    : center_(center),
      bottom_radius_(bottom_radius),
      top_radius_(top_radius),
      half_height_(half_height) {
    require_positive(half_height, "Cone half height");
    if (!(bottom_radius >= 0) || !(top_radius >= 0) || !(std::max(bottom_radius, top_radius) > 0))
        throw std::invalid_argument("Cone radii must be >= 0 and not both 0, got bottom " +
                                    std::to_string(bottom_radius) + ", top " +
                                    std::to_string(top_radius));
}

double Cone::value(const Vec3& p) const {
    const Vec3 d = p - center_;
    return cone_meridian(Vec2(std::hypot(d.x(), d.y()), d.z()), bottom_radius_, top_radius_,
                         half_height_)
        .value;
}

Vec3 Cone::gradient(const Vec3& p) const {
    const Vec3 d = p - center_;
    const MeridianDistance m = cone_meridian(Vec2(std::hypot(d.x(), d.y()), d.z()), bottom_radius_,
                                             top_radius_, half_height_);
    return from_meridian(d, m.gradient);
}

void Cone::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const Vec3 d = p - center_;
    const double h = half_height_, r0 = bottom_radius_, r1 = top_radius_;
    // The side: the line through (r0, -h) and (r1, h) of the meridian plane, turned to the
    // generator along the unit radial vector e.
    const Vec2 slant = Vec2(2 * h, r0 - r1) / std::hypot(r1 - r0, 2 * h);
    auto side = [&](const Vec3& e) {
        const Vec2 q(d.x() * e.x() + d.y() * e.y(), d.z());
        return Piece{slant.dot(q - Vec2(r0, -h)), slant[0] * e + slant[1] * Vec3::UnitZ()};
    };
    const Vec3 radial = radial_direction(d);
    const double apex_z = r0 == 0 ? -h : h;
    const bool near_apex =
        (r0 == 0 || r1 == 0) && (d - Vec3(0, 0, apex_z)).norm() <= std::max(tolerance, 0.0);
    if (!near_apex) {
        Piece pieces[3];
        int count = 0;
        pieces[count++] = side(radial);
        if (r0 > 0) pieces[count++] = {-d.z() - h, -Vec3::UnitZ()};
        if (r1 > 0) pieces[count++] = {d.z() - h, Vec3::UnitZ()};
        add_pieces_near_max(pieces, count, tolerance, out);
        return;
    }
    // At an apex the cap (if any) is 2 half_height away; the side counts three times.
    const double third = 2 * std::acos(-1.0) / 3;
    for (int k = 0; k < 3; ++k) {
        const double c = std::cos(k * third), s = std::sin(k * third);
        out.push_back(
            side(Vec3(c * radial.x() - s * radial.y(), s * radial.x() + c * radial.y(), 0)));
    }
}

Box3 Cone::bounds() const {
    const double r = std::max(bottom_radius_, top_radius_);
    const Vec3 h(r, r, half_height_);
    return {center_ - h, center_ + h};
}

}  // namespace hexmesh

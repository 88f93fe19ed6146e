// Analytic primitive bodies: sphere, ellipsoid, box, capped cylinder, torus, capped cone.
//
// Conventions shared by every class here:
// - u < 0 inside, u > 0 outside, in geometry units;
// - value() is the exact signed distance except for Ellipsoid (first-order distance);
// - gradient() is analytic for the exact ones; where the distance has a kink (medial
//   surface, box edges seen from inside, axis of revolution) it returns one of the
//   one-sided gradients, always a unit vector;
// - "axis z" means the body is symmetric about the line through `center` along +z;
// - active_pieces() of the bodies with sharp edges lists face planes, the side and caps:
//   the body is their max, so a piece is active when within tolerance of the largest.
// Constructors throw std::invalid_argument on non-positive sizes.
#pragma once

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

class Sphere : public ImplicitFunction {
  public:
    Sphere(const Vec3& center, double radius);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;  // +z at the centre
    Box3 bounds() const override;

  private:
    Vec3 center_;
    double radius_;
};

// u = g / |grad g| with g = sqrt(sum (x_i / a_i)^2) - 1: |grad u| = 1 on u = 0 and u is
// the exact distance along the three axes. At the centre u = -min(a_i).
// Gradient: the base-class central differences.
class Ellipsoid : public ImplicitFunction {
  public:
    Ellipsoid(const Vec3& center, const Vec3& semi_axes);
    double value(const Vec3& p) const override;
    Box3 bounds() const override;

  private:
    Vec3 center_;
    Vec3 semi_axes_;
};

// Axis-aligned box |x_i - c_i| <= h_i with sharp edges and corners.
class Box : public ImplicitFunction {
  public:
    Box(const Vec3& center, const Vec3& half_sizes);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;  // ties inside: the lowest axis index
    // The face planes on p's side, at most one per axis: 2 on an edge, 3 at a corner.
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;

  private:
    Vec3 center_;
    Vec3 half_sizes_;
};

// Capped cylinder, axis z: rho <= radius, |z - c_z| <= half_height.
class Cylinder : public ImplicitFunction {
  public:
    Cylinder(const Vec3& center, double radius, double half_height);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    // The side (rho - radius, radial gradient; +x on the axis) and the cap on p's side.
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;

  private:
    Vec3 center_;
    double radius_;
    double half_height_;
};

// Ring torus, axis z, symmetric about the plane z = c_z: 0 < minor_radius < major_radius.
class Torus : public ImplicitFunction {
  public:
    Torus(const Vec3& center, double major_radius, double minor_radius);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    Box3 bounds() const override;

  private:
    Vec3 center_;
    double major_radius_;
    double minor_radius_;
};

// Capped cone (frustum), axis z: radius bottom_radius at z = c_z - half_height, top_radius
// at z = c_z + half_height, linear in between. Either radius may be 0 (apex), not both.
class Cone : public ImplicitFunction {
  public:
    Cone(const Vec3& center, double bottom_radius, double top_radius, double half_height);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    // The side (signed distance to the tangent plane along p's generator) and the caps of
    // non-zero radius. Within tolerance of an apex: the tangent planes along three
    // generators 120 degrees apart instead of one, so the apex has 3 normals (a corner).
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;

  private:
    Vec3 center_;
    double bottom_radius_;
    double top_radius_;
    double half_height_;
};

}  // namespace hexmesh

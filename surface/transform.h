// Rigid motion plus uniform scaling of a body, keeping it a signed distance.
#pragma once

#include "hexmesh/core/types.h"
#include "surface/body.h"

namespace hexmesh {

// The child body moved by x = translation + scale * rotation * y (y in child coordinates):
// u(x) = scale * child(rotation^T (x - translation) / scale), so an exact signed distance
// stays exact. Throws std::invalid_argument if child is null, rotation is not orthonormal
// (to 1e-9) or scale is not > 0.
class Transformed : public ImplicitFunction {
  public:
    Transformed(Body child, const Vec3& translation, const Mat3& rotation = Mat3::Identity(),
                double scale = 1.0);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;  // rotation * child gradient
    // The child's pieces (tolerance / scale in child units): values * scale, gradients rotated.
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;  // axis-aligned hull of the moved child box's 8 corners

  private:
    Vec3 to_child(const Vec3& p) const;

    Body child_;
    Vec3 translation_;
    Mat3 rotation_;
    double scale_;
};

// Right-handed rotation by `degrees` about `axis` (any non-zero length).
Mat3 rotation_from_axis_angle(const Vec3& axis, double degrees);

}  // namespace hexmesh

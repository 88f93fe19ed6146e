#include "surface/transform.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hexmesh {

Transformed::Transformed(Body child, const Vec3& translation, const Mat3& rotation, double scale)
    : child_(std::move(child)), translation_(translation), rotation_(rotation), scale_(scale) {
    if (!child_) throw std::invalid_argument("Transformed: the child body is null");
    if (!(scale > 0) || !std::isfinite(scale))
        throw std::invalid_argument("Transformed: scale must be a positive finite number, got " +
                                    std::to_string(scale));
    const double error = (rotation.transpose() * rotation - Mat3::Identity()).norm();
    if (!(error < 1e-9))
        throw std::invalid_argument(
            "Transformed: rotation must be orthonormal (|R^T R - I| = " + std::to_string(error) +
            "); build it with rotation_from_axis_angle");
}

Vec3 Transformed::to_child(const Vec3& p) const {
    return rotation_.transpose() * (p - translation_) / scale_;
}

double Transformed::value(const Vec3& p) const {
    return scale_ * child_->value(to_child(p));
}

Vec3 Transformed::gradient(const Vec3& p) const {
    return rotation_ * child_->gradient(to_child(p));
}

void Transformed::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const std::size_t first = out.size();
    child_->active_pieces(to_child(p), tolerance / scale_, out);
    for (std::size_t k = first; k < out.size(); ++k) {
        out[k].value *= scale_;
        out[k].gradient = rotation_ * out[k].gradient;
    }
}

Box3 Transformed::bounds() const {
    const Box3 b = child_->bounds();
    Box3 out{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 y((corner & 1) ? b.hi.x() : b.lo.x(), (corner & 2) ? b.hi.y() : b.lo.y(),
                     (corner & 4) ? b.hi.z() : b.lo.z());
        const Vec3 x = translation_ + scale_ * (rotation_ * y);
        out.lo = out.lo.cwiseMin(x);
        out.hi = out.hi.cwiseMax(x);
    }
    return out;
}

Mat3 rotation_from_axis_angle(const Vec3& axis, double degrees) {
    const double n = axis.norm();
    if (!(n > 0) || !std::isfinite(n))
        throw std::invalid_argument("rotation_from_axis_angle: the axis must be a non-zero vector");
    const double radians = degrees * std::acos(-1.0) / 180.0;
    return Eigen::AngleAxisd(radians, axis / n).toRotationMatrix();
}

}  // namespace hexmesh

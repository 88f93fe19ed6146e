// Basic value types shared by every module: 3D points, node ids, index boxes.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace hexmesh {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Node and cell ids. 64-bit so flat indices of large structured grids never overflow.
using Id = std::int64_t;

// Axis-aligned box [lo, hi] in geometry units.
struct Box3 {
    Vec3 lo = Vec3::Zero();
    Vec3 hi = Vec3::Zero();

    Vec3 center() const { return 0.5 * (lo + hi); }
    Vec3 size() const { return hi - lo; }
    double diagonal() const { return (hi - lo).norm(); }
};

// The smallest box holding every point (lo = hi = 0 for none).
template <class Points>
Box3 bounds_of(const Points& points) {
    Box3 box;
    bool first = true;
    for (const Vec3& p : points) {
        box.lo = first ? p : Vec3(box.lo.cwiseMin(p));
        box.hi = first ? p : Vec3(box.hi.cwiseMax(p));
        first = false;
    }
    return box;
}

}  // namespace hexmesh

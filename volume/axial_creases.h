// The creases of a body that run around an axis of the O-H grid's core, found along rays
// through the cube faces across it, and the axis that has round ones.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/types.h"

namespace hexmesh {

// The creases of a body around an axis, as seen from `centre` by the rays ray(t) through the
// two cube faces across the axis: along the 8 half-lines t = w d +- axis (d = +-b, +-c,
// 0 < w < 1) to the faces' edge midpoints, and the 8 half-lines t = v (d + d') +- axis to
// their corners, the rays are placed on u = 0 (volume/surface_placement.h) and the creases
// crossed are found (surface/implicit_features.h) and located exactly; those within 0.05 of
// the axis or of `outer` (the frame, where the patch edges are) are left out. Throws
// std::invalid_argument when a ray misses u = 0 (the body is not star-shaped).
struct AxialCreases {
    std::vector<double> radius;  // w of each crease along the edge-midpoint half-lines, ascending
    std::vector<double> reach;   // its distance from the axis along the diagonals (t plane)
    std::vector<int> seen;       // on how many of the 8 edge-midpoint half-lines it lies
    std::vector<double> w;       // the samples of w
    std::vector<Vec3> meridian;  // the wall at those samples along the first half-line
};
AxialCreases find_axial_creases(const ImplicitFunction& body, const Vec3& centre,
                                const std::function<Vec3(const Vec3&)>& ray, int axis, double outer,
                                double length_scale);

// The axis whose round creases run around it: the one with the most creases met on at least
// 4 of their 8 edge-midpoint half-lines (all four of one end, say) and reaching along the
// diagonals less than 1.2 times their radius (circles, not squares: a square crease around an
// axis runs along the lines of one core block's patch, corners included); -1 when no axis
// has one.
int choose_axis(const std::array<AxialCreases, 3>& creases);

}  // namespace hexmesh

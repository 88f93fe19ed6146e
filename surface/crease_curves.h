// Sharp creases of implicit bodies (analytic, CSG, transformed) as polylines and corners, the
// input of CGAL's Mesh_3 feature protection (Mesh_domain_with_polyline_features_3::add_features).
#pragma once

#include <vector>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

struct CreaseCurves {
    // Points on the creases, consecutive ones about `step` apart (0.25 to 2 step; less only
    // for a crease that short), at least 2 per polyline. An open polyline runs from corner to
    // corner: its end points are bitwise equal to entries of `corners` (CGAL joins polylines at
    // equal end points). A closed loop repeats its first point at the end, bitwise. The one
    // exception: a crease that fades out without a corner ends at a point not in `corners`.
    std::vector<std::vector<Vec3>> polylines;
    // Distinct corners: surface points where pieces with normals spanning 3D meet (a box
    // corner, a cone apex). A corner may end no polyline (the apex of a cone).
    std::vector<Vec3> corners;
};

// The creases of `body` (all within body.bounds()); `step` (> 0, typically half the cell
// size) is the spacing of the polyline points. Seeds on a lattice of spacing `step` over the
// bounds: projects the lattice points near two or more pieces onto their crease
// (project_to_crease) and the ones near three onto their corner (snap_to_corner), then
// follows each crease from a seed in both directions until it reaches a corner, closes or
// fades out; creases too short to hold a seed are then followed from their corners. A smooth
// body gives no polylines. Deterministic; costs about (bounds diagonal / step)^3 value()
// calls. Throws std::invalid_argument unless step > 0 and the lattice has < 1e9 points.
CreaseCurves trace_creases(const ImplicitFunction& body, double step);

}  // namespace hexmesh

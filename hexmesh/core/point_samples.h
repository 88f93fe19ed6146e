// Bodies given by samples: oriented points (a point cloud) and stacks of planar cross-sections.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

// A point cloud with one normal per point. normals[i] belongs to points[i] and points out
// of the body (not necessarily unit length; never zero). Geometry units.
struct OrientedPoints {
    std::vector<Vec3> points;
    std::vector<Vec3> normals;
};

// One planar cross-section of a body, in the plane z = const: closed polylines of (x, y)
// points, each given once (the closing segment from the last point back to the first is
// implied). A point (x, y) is inside the section when a ray from it crosses the polylines
// an odd number of times (even-odd rule), so a hole is a polyline inside another one.
struct Section {
    double z = 0;
    std::vector<std::vector<Eigen::Vector2d>> loops;  // each at least 3 points
};

// Sections in strictly increasing z, at least 2.
struct SectionStack {
    std::vector<Section> sections;
};

}  // namespace hexmesh

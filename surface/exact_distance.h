// Exact distance to a triangle surface (CGAL AABB tree): the reference for the sampled SDF
// in tests and for surface-fidelity (Hausdorff) measures.
#pragma once

#include <memory>
#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

// Zero-area triangles are skipped (they add nothing to the distance). Queries are const and
// safe to run concurrently.
class ExactDistance {
  public:
    // Throws std::invalid_argument if the surface has no triangle of non-zero area.
    explicit ExactDistance(const TriangleSurface& surface);
    ~ExactDistance();
    ExactDistance(const ExactDistance&) = delete;
    ExactDistance& operator=(const ExactDistance&) = delete;

    double distance(const Vec3& p) const;  // unsigned, >= 0
    Vec3 closest_point(const Vec3& p) const;
    // Unit normal of the triangle that holds closest_point(p) (orientation as in the file).
    Vec3 closest_normal(const Vec3& p) const;
    // Index (into the surface's triangles) of the triangle that holds closest_point(p).
    int closest_triangle(const Vec3& p) const;

    // Generalized winding number: the signed solid angle of the triangles seen from p over
    // 4 pi. 1 inside and 0 outside a closed surface oriented counter-clockwise from
    // outside; near 1 or 0 away from the holes of an open one. O(#triangles) per call.
    double winding_number(const Vec3& p) const;

    // distance(p), negative where winding_number(p) > 0.5.
    double signed_distance(const Vec3& p) const;

  private:
    struct Tree;
    std::unique_ptr<Tree> tree_;
    TriangleSurface surface_;
};

// Largest distance from the points to the surface: one side of the Hausdorff distance
// (0 for no point).
double max_distance_to(const ExactDistance& surface, const std::vector<Vec3>& points);

}  // namespace hexmesh

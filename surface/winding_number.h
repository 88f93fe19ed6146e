// Fast generalized winding number of a triangle soup (Barill et al. 2018, first order):
// inside/outside that tolerates holes, for signing distances of open surfaces.
#pragma once

#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

// w(p) = sum of the signed solid angles of the triangles seen from p, over 4 pi: 1 inside
// and 0 outside a closed surface oriented counter-clockwise from outside, and close to
// that away from small holes (a hole costs its own solid angle). A bounding-volume tree
// replaces the triangles of a far cluster (distance > accuracy * cluster radius) by their
// area-weighted normal (a dipole): error below 0.05 for accuracy 2 (far below the 1/2 that
// decides inside), cost O(log T) per query.
// Queries are const and safe to run concurrently.
class WindingNumber {
  public:
    explicit WindingNumber(const TriangleSurface& surface, double accuracy = 2.0);
    double operator()(const Vec3& p) const;

  private:
    struct Node {
        Vec3 lo, hi;
        Vec3 centre;       // area-weighted centroid of the cluster
        Vec3 normal;       // sum of area-weighted normals (|n| = area)
        double radius;     // of a ball about centre holding the cluster
        int first, count;  // triangles order[first, first + count) when a leaf
        int left = -1, right = -1;
    };
    int build(int first, int count);

    TriangleSurface surface_;
    std::vector<int> order_;  // triangle ids, grouped by leaf
    std::vector<Node> nodes_;
    double accuracy_;
};

}  // namespace hexmesh

// The sharp creases and corners of a triangle surface as the smooth pieces of
// ImplicitFunction::active_pieces: near a crease, the planes of the two triangles that meet
// along it; near a corner, the planes of all triangles along its creases. With them a
// surface read from an STL has the same feature machinery as an analytic or CSG body
// (surface/implicit_features.h: classification, crease tangent, projection onto creases and
// corners), and the grid generator snaps wall nodes onto its edges.
#pragma once

#include <memory>
#include <vector>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

class MeshCreases {
  public:
    // Creases are the edges of two triangles whose normals turn by more than angle_degrees
    // (surface/sharp_features.h; open and non-manifold edges are not creases here); corners
    // are the points where 1 or at least 3 of them meet. Each triangle's plane is oriented
    // out of the body given by `body` (its value is compared a small `probe` distance on
    // both sides of the triangle's centroid), whatever the file's orientation.
    // angle_degrees >= 180: no crease at all.
    MeshCreases(const TriangleSurface& surface, double angle_degrees, const ImplicitFunction& body,
                double probe);
    ~MeshCreases();
    MeshCreases(const MeshCreases&) = delete;
    MeshCreases& operator=(const MeshCreases&) = delete;

    int crease_edges() const;
    int corners() const;

    // The pieces at p, appended to `out`, when p is near a crease or a corner: the planes of
    // the nearest crease edge, or of the nearer corner at its ends when p is nearer than
    // tolerance / sin(angle) to it, keeping those whose value at p is within `tolerance` of
    // the value nearest to zero. Returns false, appending nothing, when no crease edge lies
    // within tolerance / sin(angle) of p, when that nearest plane value is more than
    // tolerance + slack from `value` (the body's value at p; slack covers its sampling
    // error: the planes belong to a crease elsewhere), or when fewer than two planes are
    // kept: there the surface is smooth and the caller supplies its own piece.
    bool add_pieces(const Vec3& p, double tolerance, double value, double slack,
                    std::vector<ImplicitFunction::Piece>& out) const;

  private:
    struct Index;
    std::unique_ptr<Index> index_;
};

}  // namespace hexmesh

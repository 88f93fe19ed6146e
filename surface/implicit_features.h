// Sharp features of implicit bodies (analytic, CSG, transformed) from their active smooth
// pieces: crease / corner classification, crease direction, projection onto creases and
// corners (the tangent cone of docs/architecture.md#boundary-conditions; triangle surfaces use
// sharp_features.h).
#pragma once

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/vertex_kind.h"

namespace hexmesh {

// Pieces whose unit normals are within this angle of each other, or of each other's
// opposite, count as one piece: they make no crease.
constexpr double same_normal_degrees = 1.0;

// What the active pieces at a surface point make: smooth (one normal), crease (normals
// spanning a plane: faces meeting along a line, 1 dof) or corner (normals spanning 3D).
enum class FeatureKind { smooth, crease, corner };

// The constraint of a boundary vertex at such a point: slip, feature_edge or corner.
constexpr VertexKind boundary_vertex_kind(FeatureKind kind) {
    switch (kind) {
        case FeatureKind::smooth:
            return VertexKind::slip;
        case FeatureKind::crease:
            return VertexKind::feature_edge;
        case FeatureKind::corner:
            return VertexKind::corner;
    }
    return VertexKind::slip;
}

// The distinct normals among u.active_pieces(p, tolerance) (tolerance a length, typically
// 1e-3 h; p on or near u = 0): none or one -> smooth, all perpendicular to one direction
// (within same_normal_degrees) -> crease, else corner. Pieces with a zero or non-finite
// gradient are ignored.
FeatureKind classify_surface_point(const ImplicitFunction& u, const Vec3& p, double tolerance);

// Unit n_a x n_b of the two active pieces (within tolerance) with distinct normals nearest to
// zero at p; its sign follows the order of the pieces (not meaningful). At a corner: the
// crease of its two pieces nearest to zero. Zero vector where p is smooth.
Vec3 crease_tangent(const ImplicitFunction& u, const Vec3& p, double tolerance);

// The nearby point of a crease: where the two pieces nearest to zero (with distinct normals,
// sought within 4 length_scale of the combination's value) both vanish. Minimum-norm
// Gauss-Newton steps x <- x - J^T (J J^T)^-1 g, g = (u_a, u_b), J rows the pieces' gradients,
// the pair re-selected at every point, each step at most 8 length_scale long and halved
// until the larger |u_a|, |u_b| decreases; stops when it is < 1e-12 length_scale.
// Meant for p up to about one length_scale (the cell size h) from the crease; near a
// corner it lands on one of the corner's creases. Never NaN:
// - fewer than two distinct pieces at p (a smooth place): project_to_surface(u, p).point;
// - a step that halving cannot make decrease, or 50 steps: the best point reached (it
//   vanishes the pair only approximately; the caller may check the pieces there).
// Throws std::invalid_argument unless length_scale > 0.
Vec3 project_to_crease(const ImplicitFunction& u, const Vec3& p, double length_scale);

// The same with the three pieces nearest to zero whose normals span 3D (Newton on 3
// equations): the nearby corner. Fewer than three such pieces at p: project_to_crease.
Vec3 snap_to_corner(const ImplicitFunction& u, const Vec3& p, double length_scale);

}  // namespace hexmesh

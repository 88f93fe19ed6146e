// Vertex constraints: the directions each vertex may move in and the projection back afterwards.
#pragma once

#include <vector>

#include "untangle/problem.h"

namespace hexmesh::untangle {

// Per vertex, a 3 x 3 matrix whose non-zero columns are an orthonormal basis of the allowed
// displacements at x (docs/architecture.md#boundary-conditions: L_k): identity inside, [l1 l2 0] on
// a slip vertex (l1, l2 tangent to u = 0), [t 0 0] on a feature edge, zero when fixed or a corner.
std::vector<Mat3> movement_bases(const Problem& problem, const std::vector<Vec3>& x);

// Number of allowed directions of each kind (3, 2, 1, 0): the first columns of its basis.
int active_directions(VertexKind kind);

// The projection V: slip vertices back onto u = 0, feature-edge vertices onto their crease.
// Interior and fixed vertices are left as they are.
void project_constrained(const Problem& problem, std::vector<Vec3>& x);

// Throws std::invalid_argument when a kind needs data the problem lacks (a surface for slip,
// the edge functions for feature edges, the normal for triangles) or a triangle has an
// interior vertex, std::runtime_error, naming its place, when a surface
// triangle has no normal at the problem's points.
void check_constraints(const Problem& problem);

}  // namespace hexmesh::untangle

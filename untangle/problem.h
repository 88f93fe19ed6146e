// What the untangler optimizes: vertices, their constraints, and tetrahedral elements with targets.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "hexmesh/core/types.h"
#include "hexmesh/core/vertex_kind.h"
#include "untangle/tet_energy.h"

namespace hexmesh::untangle {

// A mesh split into tetrahedra (hex corner tets, plain tets). Vertices move according to
// their kind: interior (free), slip (in the tangent plane of u = 0, then projected back by
// V), feature_edge (along the crease tangent, then projected onto the crease), corner and
// fixed (never). The geometry comes as functions of (vertex id, position), so the untangler
// knows nothing of how the surface is represented.
struct Problem {
    std::vector<Vec3> points;                // #V
    std::vector<VertexKind> kinds;           // #V
    std::vector<std::array<Id, 4>> tets;     // #T, vertex ids, positively oriented target
    std::vector<TetTarget> targets;          // #T
    std::function<Vec3(Id, const Vec3&)> surface_normal;      // slip: normal of u = 0 (grad u)
    std::function<Vec3(Id, const Vec3&)> project_to_surface;  // slip: the projection V
    std::function<Vec3(Id, const Vec3&)> edge_tangent;        // feature_edge: crease direction
    std::function<Vec3(Id, const Vec3&)> project_to_edge;     // feature_edge: onto the crease
    double length_scale = 1;  // typical edge length: tolerances are relative to it
};

}  // namespace hexmesh::untangle

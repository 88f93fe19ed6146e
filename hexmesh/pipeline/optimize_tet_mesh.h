// The variational optimizer of a tetrahedral mesh on a case's body: the sizing function and the
// targets it gives, the boundary's geometry and the vertices' kinds, the optimization itself
// (boundary vertices sliding on the body, then reweighted rounds that lift the worst tets) and
// the fallback to another mesh's vertices where the optimized one is worse.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "hexmesh/core/vertex_kind.h"
#include "hexmesh/pipeline/boundary_geometry.h"
#include "io/case_file.h"
#include "untangle/untangle.h"
#include "volume/tet_mesh.h"

namespace hexmesh {

using SizingFunction = std::function<double(const Vec3&)>;

// h(x) = min(cell_size, wall_cell_size + grading |u(x)|) of the case's tet_mesh section
// (sizes resolved as TetMeshSpec documents), u = `body`.
SizingFunction tet_sizing(const Case& c, std::shared_ptr<const ImplicitFunction> body);

// The size at the wall and in the core of the case's tet mesh.
struct TetSizes {
    double wall = 0, core = 0;
};
TetSizes tet_sizes(const Case& c, const ImplicitFunction& body);

// The creases of a surface file the tet case protects and slides on: edges turning by more
// than tet_mesh.feature_angle, and none on a faceted scan, where the edges beside them turning
// by between half that angle and it are at least half as many (surface/sharp_features.h).
// CGAL's protection of a scan's thousands of short, crossing "creases" does not end.
FeatureOptions tet_crease_options(const Case& c);

// Where the boundary vertices of a mesh of the case's body slide: the triangles of a surface
// file (creases by tet_crease_options), else the implicit body.
BoundaryGeometry case_boundary(const Case& c, std::shared_ptr<const ImplicitFunction> body,
                               double length_scale);

// Vertex kinds from CGAL's dimensions (3 interior, 2 slip, 1 crease, 0 corner).
std::vector<VertexKind> kinds_from_dimensions(const std::vector<std::int8_t>& dimension);

// Vertex kinds from the mesh's boundary faces (faces of one tet): interior inside, else as
// boundary.kind_at(x, reach) says.
std::vector<VertexKind> boundary_kinds(const TetMesh& mesh, const BoundaryGeometry& boundary,
                                       double reach);

// Regular targets (docs/architecture.md#the-functional: v0 from the sizing function) whose edges
// follow `size` at each tet's centroid, all scaled by one factor so that their volumes add up to
// the mesh's signed volume: the domain's volume, also while the mesh is tangled (its unsigned
// volume if the signed one is not positive). tets: 4 point ids per tet.
std::vector<untangle::TetTarget> sized_tet_targets(const std::vector<Vec3>& points,
                                                   const std::vector<Id>& tets,
                                                   const SizingFunction& size);

// The largest distance of the mesh's boundary points (on faces of one tet) to `boundary`.
double max_boundary_distance(const TetMesh& mesh, const BoundaryGeometry& boundary);

struct TetOptimization {
    untangle::UntangleResult solve;
    double max_surface_distance = 0;  // of slip, crease and corner vertices, after
    double max_crease_distance = 0;   // of crease and corner vertices, after
};

// Rounds of reweighting after the plain minimization: each tet's weight times its distortion
// phi^(power - 1), to lift the worst tets (0 rounds: the plain sum).
struct Reweighting {
    int rounds = 4;
    double power = 4;
};

// The untangler's options for tets: theta = 0.3, shape weighing more than for hex cells (the
// dihedral angles are a shape measure); the rest as UntangleOptions has them.
untangle::UntangleOptions tet_untangle_options();

// Moves every boundary vertex onto the part of the surface its kind names, then untangles (the
// boundary held first when the mesh is tangled) and optimizes `mesh` with the targets of
// sized_tet_targets, then reweights (the round with the largest smallest dihedral angle is kept).
// kinds: one per point.
TetOptimization optimize_tet_mesh(TetMesh& mesh, const std::vector<VertexKind>& kinds,
                                  const BoundaryGeometry& boundary, const SizingFunction& size,
                                  const untangle::UntangleOptions& options,
                                  const Reweighting& reweighting = {});

// result.max_surface_distance and max_crease_distance of `mesh`'s slip, crease and corner
// points (kinds: one per point).
void measure_boundary_distances(const TetMesh& mesh, const std::vector<VertexKind>& kinds,
                                const BoundaryGeometry& boundary, TetOptimization& result);

// Moves back to `fallback`'s positions the vertices of `optimized` (a mesh of the same tets
// as `fallback`, its vertices moved) wherever it is worse: the four vertices of every tet whose
// smallest dihedral angle is under `bound` degrees, or whose orientation differs from
// fallback's, again until no such tet keeps a moved vertex. Each tet of the result is then
// fallback's own (all four vertices back) or at least `bound`. Returns the number of vertices
// moved back.
Id keep_fallback_where_worse(const TetMesh& fallback, TetMesh& optimized, double bound);

// The worst tets' points moved to raise the smallest dihedral angle directly, where the
// functional's sum does not aim: the tets under `below_degrees`, worst first, each of their
// points (but fixed ones and corners) by a compass search on the smallest angle of the tets
// around it, until that reaches `below_degrees` (interior points in 14 directions, surface
// points in 8 of the tangent plane, crease points along the crease, each step placed back on
// its part of the boundary and judged there). A move is kept when it raises that angle and
// every tet around the point stays positively oriented (exact predicate), so the mesh's
// smallest angle never falls. Up to `passes` passes, until one moves nothing. Returns the
// number of moves.
Id raise_smallest_angles(TetMesh& mesh, const std::vector<VertexKind>& kinds,
                         const BoundaryGeometry& boundary, double below_degrees, int passes = 8);

}  // namespace hexmesh

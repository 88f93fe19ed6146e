// The `tetmesh` job: a tetrahedral mesh of a case's body by CGAL's Delaunay refinement, made
// sliver-free by the variational optimizer (boundary vertices sliding on the body) and flips,
// and compared with CGAL's own sliver removal on the same mesh.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/vertex_kind.h"
#include "hexmesh/pipeline/boundary_geometry.h"
#include "hexmesh/quality/tet_quality.h"
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

// Where the boundary vertices of a mesh of the case's body slide: the triangles of a surface
// file (creases by tet_mesh.feature_angle), else the implicit body.
BoundaryGeometry case_boundary(const Case& c, std::shared_ptr<const ImplicitFunction> body,
                               double length_scale);

// Vertex kinds from CGAL's dimensions (3 interior, 2 slip, 1 crease, 0 corner).
std::vector<VertexKind> kinds_from_dimensions(const std::vector<std::int8_t>& dimension);

// Vertex kinds from the mesh's boundary faces (faces of one tet): interior inside, else as
// boundary.kind_at(x, reach) says.
std::vector<VertexKind> boundary_kinds(const TetMesh& mesh, const BoundaryGeometry& boundary,
                                       double reach);

// Regular targets (DESIGN §4: v0 from the sizing function) whose edges follow `size` at each
// tet's centroid, all scaled by one factor so that their volumes add up to the mesh's signed
// volume: the domain's volume, also while the mesh is tangled (its unsigned volume if the
// signed one is not positive). tets: 4 point ids per tet.
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

// Moves back to `fallback`'s positions the vertices of `optimized` (a mesh of the same tets
// as `fallback`, its vertices moved) wherever it is worse: the four vertices of every tet whose
// smallest dihedral angle is under `bound` degrees, or whose orientation differs from
// fallback's, again until no such tet keeps a moved vertex. Each tet of the result is then
// fallback's own (all four vertices back) or at least `bound`. Returns the number of vertices
// moved back.
Id keep_fallback_where_worse(const TetMesh& fallback, TetMesh& optimized, double bound);

struct TetCaseOptions {
    bool compare_cgal = false;  // also run CGAL's perturb + exude on the refined mesh
    // Boundary caps below this dihedral angle are removed before optimizing (0: none).
    double cap_degrees = 20;
    // Cycles of flips (edge removal of 3 to 7 tets, 2-3) on the tets below flip_degrees, each
    // followed by the optimization again; a cycle that does not raise the smallest angle is
    // undone and ends them.
    int flip_cycles = 3;
    double flip_degrees = 30;
    double cgal_sliver_bound = 0;  // compare_cgal: TetMeshOptions::cgal_sliver_bound
    double cgal_time_limit = 0;
    untangle::UntangleOptions untangle = tet_untangle_options();
    Reweighting reweighting;
};

struct TetCaseResult {
    TetMeshGeneration generation;
    TetMesh mesh;  // the optimized mesh
    Id crease_polylines = 0, corners = 0, caps_removed = 0, edge_removals = 0, flips_23 = 0;
    TetQualityReport refined, optimized;
    std::optional<TetQualityReport> cgal;
    double refined_surface_distance = 0, cgal_surface_distance = 0;  // max over boundary vertices
    TetOptimization optimization;
    double wall_size = 0, core_size = 0;
    double seconds_features = 0, seconds_optimize = 0;
    // Where `mesh` comes from: the refined mesh optimized ("variational"), or, when that left
    // slivers or ended under CGAL's perturb + exude, that mesh optimized ("variational from
    // CGAL's"), or that mesh optimized with its vertices held where the optimization would bring
    // a tet under that mesh's smallest angle ("CGAL's, optimized"), or that mesh itself
    // ("CGAL's"), whichever has the largest smallest angle (then the largest mean).
    std::string start = "variational";
    Id cgal_vertices_held = 0;  // "CGAL's, optimized": vertices left at CGAL's places
};

// The whole job; one progress line per phase to `log`. The refined mesh is optimized; where
// slivers remain or CGAL's perturb + exude of it (computed then if compare_cgal did not) has
// a larger smallest dihedral angle, that mesh optimized too, and the best of the three kept. Throws
// InputError for a case it cannot mesh (an exterior domain, a wall cell size too small to trace the
// creases at).
TetCaseResult run_tet_case(const Case& c, const TetCaseOptions& options, std::ostream& log);

// The comparison table: refined, CGAL perturb + exude (when run), variational.
std::string format_tet_comparison(const TetCaseResult& r);

}  // namespace hexmesh

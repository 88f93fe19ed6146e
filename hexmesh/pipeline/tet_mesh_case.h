// The `tetmesh` job: a tetrahedral mesh of a case's body by CGAL's Delaunay refinement, made
// sliver-free by the variational optimizer (boundary vertices sliding on the body), flips, and
// last moves and point insertions on the worst tets, and compared with CGAL's own sliver removal on
// the same mesh.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/pipeline/optimize_tet_mesh.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/case_file.h"
#include "untangle/untangle.h"
#include "volume/tet_mesh.h"

namespace hexmesh {

struct TetCaseOptions {
    bool compare_cgal = false;  // also run CGAL's perturb + exude on the refined mesh
    // Boundary caps below this dihedral angle are removed before optimizing (0: none).
    double cap_degrees = 20;
    // Cycles of flips (edge removal of 3 to 7 tets, 2-3) on the tets below flip_degrees, each
    // followed by the optimization again; a cycle that does not raise the smallest angle is
    // undone and ends them.
    int flip_cycles = 3;
    double flip_degrees = 30;
    // Last, the points of the tets below raise_degrees moved to raise their smallest dihedral
    // angle, and points inserted in those whose four points are on the boundary (0: none).
    double raise_degrees = 15;
    double cgal_sliver_bound = 0;  // compare_cgal: TetMeshOptions::cgal_sliver_bound
    double cgal_time_limit = 0;
    untangle::UntangleOptions untangle = tet_untangle_options();
    Reweighting reweighting;
};

struct TetCaseResult {
    TetMeshGeneration generation;
    TetMesh mesh;  // the optimized mesh
    Id crease_polylines = 0, corners = 0, caps_removed = 0, edge_removals = 0, flips_23 = 0;
    Id points_inserted = 0;  // in tets of four boundary points (raise_degrees)
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

// Throws InputError when `output` (or `cgal_output`, unless empty) is not a volume mesh file
// that can be written (check_volume_mesh_output), std::invalid_argument when both name the same
// file.
void check_tet_outputs(const std::string& output, const std::string& cgal_output);

// Writes r.mesh to `output` and, unless `cgal_output` is empty, CGAL's perturbed and exuded mesh
// to it (both or neither); with `report`, NAME.report.html beside `output` (title: `title`).
// Returns the paths written, in that order.
std::vector<std::string> write_tet_case(const TetCaseResult& r, const Case& c,
                                        const std::string& output, const std::string& cgal_output,
                                        bool report, const std::string& title);

// The comparison table: refined, CGAL perturb + exude (when run), variational.
std::string format_tet_comparison(const TetCaseResult& r);

}  // namespace hexmesh

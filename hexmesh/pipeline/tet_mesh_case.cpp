#include "hexmesh/pipeline/tet_mesh_case.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/tet_report.h"
#include "io/report_page.h"
#include "io/volume_mesh_io.h"
#include "surface/crease_curves.h"
#include "surface/sharp_features.h"
#include "untangle/tet_energy.h"
#include "volume/tet_flips.h"

namespace hexmesh {
namespace {

// Creases and corners for CGAL's feature protection: a surface file's sharp edges as
// case_boundary finds them (tet_crease_options), or the creases of the implicit body traced at
// spacing `step`. `noise` (surface files): why a scan's creases were all dropped, else empty.
CreaseCurves body_creases(const Case& c, const ImplicitFunction& body, double step,
                          std::string& noise) {
    CreaseCurves curves;
    if (const auto surface = reference_surface(c.geometry)) {
        const FeatureCurves f = detect_sharp_features(*surface, tet_crease_options(c));
        for (const auto& chain : f.chains) {
            std::vector<Vec3> line;
            for (int id : chain) line.push_back(surface->points[id]);
            curves.polylines.push_back(std::move(line));
        }
        for (int id : f.corners) curves.corners.push_back(surface->points[id]);
        if (f.noise)
            noise = fmt::format(
                "{} edges turn by more than {:g} degrees, and {} beside them by {:g} to {:g}: the "
                "facets of a scan, not sharp edges, and not protected",
                f.turning_edges, c.tet_mesh.feature_angle, f.half_turning_edges,
                0.5 * c.tet_mesh.feature_angle, c.tet_mesh.feature_angle);
        return curves;
    }
    try {
        return trace_creases(body, step);
    } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format(
            "{}: tet_mesh.wall_cell_size: too small for the body to trace its creases ({})", c.path,
            e.what()));
    }
}

double max_placed_distance(const TetMesh& mesh, const std::vector<std::int8_t>& dimension,
                           const BoundaryGeometry& boundary) {
    double d = 0;
    for (size_t v = 0; v < mesh.points.size(); ++v)
        if (dimension[v] < 3) d = std::max(d, boundary.surface_distance(mesh.points[v]));
    return d;
}

// The largest distance of a crease or corner vertex (dimension 1 or 0) to the creases.
double max_crease_distance(const TetMesh& mesh, const std::vector<std::int8_t>& dimension,
                           const BoundaryGeometry& boundary) {
    double d = 0;
    for (size_t v = 0; v < mesh.points.size(); ++v)
        if (dimension[v] == 0 || dimension[v] == 1)
            d = std::max(d, boundary.crease_distance(mesh.points[v]));
    return d;
}

// `cgal` (CGAL's perturbed and exuded mesh) optimized where that keeps every tet at or above
// `bound` degrees: the vertices of the tets the optimization brings under it are held at CGAL's
// places and the rest optimized again from CGAL's mesh, up to four times; what is still under
// it then goes back to CGAL's places (keep_fallback_where_worse). The same tets as `cgal`.
struct HeldOptimization {
    TetMesh mesh;
    TetOptimization optimization;
    Id held = 0;  // vertices at CGAL's places (held, or moved back)
};

HeldOptimization optimize_where_better(const PlacedTetMesh& cgal, double bound,
                                       const BoundaryGeometry& boundary, const SizingFunction& size,
                                       const TetCaseOptions& options) {
    HeldOptimization r;
    std::vector<VertexKind> kinds = kinds_from_dimensions(cgal.dimension);
    const auto optimize = [&] {
        r.mesh = cgal.mesh;
        r.optimization =
            optimize_tet_mesh(r.mesh, kinds, boundary, size, options.untangle, options.reweighting);
    };
    optimize();
    for (int round = 0; round < 4 && r.optimization.solve.inverted_after == 0; ++round) {
        Id newly = 0;
        for (Id t = 0; t < r.mesh.num_cells(); ++t) {
            const auto angles = dihedral_angles(tet_corners(r.mesh, t));
            if (*std::min_element(angles.begin(), angles.end()) >= bound) continue;
            for (int k = 0; k < 4; ++k)
                if (kinds[r.mesh.node(t, k)] != VertexKind::fixed)
                    kinds[r.mesh.node(t, k)] = VertexKind::fixed, ++newly;
        }
        if (newly == 0) break;
        optimize();
    }
    if (r.optimization.solve.inverted_after > 0)
        r.mesh = cgal.mesh;
    else
        keep_fallback_where_worse(cgal.mesh, r.mesh, bound);
    for (size_t v = 0; v < r.mesh.points.size(); ++v)
        r.held += r.mesh.points[v] == cgal.mesh.points[v];
    return r;
}

// A mesh optimized by improve_tet_mesh, with what it took.
struct Improved {
    TetMesh mesh;
    TetOptimization optimization;
    Id caps_removed = 0, flips_23 = 0, edge_removals = 0, points_inserted = 0;
};

// The last step of improve_tet_mesh when a tet is still under options.raise_degrees: the
// worst tets' points moved to raise the smallest angle (raise_smallest_angles); then, where
// tets of four boundary points are still under it, a point inserted in each
// (insert_in_slivers), the flips and the moves again, kept if the smallest angle rises.
void raise_worst_angles(Improved& r, std::vector<VertexKind>& kinds,
                        const BoundaryGeometry& boundary, const TetCaseOptions& options,
                        std::ostream& log) {
    const double target = options.raise_degrees;
    const TetQualityReport start = measure_tet_quality(r.mesh);
    if (target <= 0 || start.inverted > 0 || start.min_dihedral >= target) return;
    const double before = start.min_dihedral;
    raise_smallest_angles(r.mesh, kinds, boundary, target);
    const double raised = measure_tet_quality(r.mesh).min_dihedral;
    log << fmt::format("smallest angle raised: {:.2f} -> {:.2f} degrees\n", before, raised)
        << std::flush;
    if (raised >= target) return;

    std::vector<bool> on_boundary(kinds.size());
    for (size_t v = 0; v < kinds.size(); ++v) on_boundary[v] = kinds[v] != VertexKind::interior;
    TetMesh inserted = r.mesh;
    r.points_inserted = insert_in_slivers(inserted, target, on_boundary);
    if (r.points_inserted == 0) return;
    std::vector<VertexKind> inserted_kinds = kinds;
    inserted_kinds.resize(inserted.points.size(), VertexKind::interior);
    const FlipResult flips = improve_by_flips(inserted, options.flip_degrees);
    raise_smallest_angles(inserted, inserted_kinds, boundary, target);
    const double with_points = measure_tet_quality(inserted).min_dihedral;
    log << fmt::format("points inserted in {} tets of four boundary points: {:.2f} degrees{}\n",
                       r.points_inserted, with_points, with_points > raised ? ", kept" : "")
        << std::flush;
    if (with_points <= raised) {
        r.points_inserted = 0;
        return;
    }
    r.mesh = std::move(inserted);
    kinds = std::move(inserted_kinds);
    r.flips_23 += flips.flips_23;
    r.edge_removals += flips.edge_removals;
}

// `start` with its boundary caps removed, optimized (optimize_tet_mesh), then cycles of flips
// and the optimization again, each kept while it raises the smallest dihedral angle, then its
// worst angles raised (raise_worst_angles).
Improved improve_tet_mesh(const PlacedTetMesh& start, const BoundaryGeometry& boundary,
                          const SizingFunction& size, const TetCaseOptions& options,
                          std::ostream& log) {
    Improved r;
    PlacedTetMesh work = start;
    r.caps_removed = options.cap_degrees > 0 ? remove_boundary_caps(work, options.cap_degrees) : 0;
    log << fmt::format("boundary caps removed: {}\n", r.caps_removed) << std::flush;
    r.mesh = std::move(work.mesh);
    std::vector<VertexKind> kinds = kinds_from_dimensions(work.dimension);
    r.optimization =
        optimize_tet_mesh(r.mesh, kinds, boundary, size, options.untangle, options.reweighting);
    // Flips where moving points is not enough, then the points again; kept while it helps.
    for (int cycle = 0; cycle < options.flip_cycles && r.optimization.solve.inverted_after == 0;
         ++cycle) {
        const TetMesh before = r.mesh;
        const double before_angle = measure_tet_quality(before).min_dihedral;
        const FlipResult f = improve_by_flips(r.mesh, options.flip_degrees);
        if (f.edge_removals + f.flips_23 == 0) break;
        const TetOptimization again =
            optimize_tet_mesh(r.mesh, kinds, boundary, size, options.untangle, options.reweighting);
        if (again.solve.inverted_after > 0 ||
            measure_tet_quality(r.mesh).min_dihedral <= before_angle) {
            r.mesh = before;
            break;
        }
        r.flips_23 += f.flips_23;
        r.edge_removals += f.edge_removals;
        r.optimization.max_surface_distance = again.max_surface_distance;
        r.optimization.max_crease_distance = again.max_crease_distance;
        r.optimization.solve.history.insert(r.optimization.solve.history.end(),
                                            again.solve.history.begin(), again.solve.history.end());
        r.optimization.solve.seconds += again.solve.seconds;
        r.optimization.solve.min_det_after = again.solve.min_det_after;
        r.optimization.solve.energy_after = again.solve.energy_after;
        log << fmt::format("flips: {} edge removals, {} 2-3\n", f.edge_removals, f.flips_23)
            << std::flush;
    }
    raise_worst_angles(r, kinds, boundary, options, log);
    measure_boundary_distances(r.mesh, kinds, boundary, r.optimization);
    return r;
}

// The mesh options of the case (size, facet distance, creases and corners to protect, CGAL's
// sliver removal when compared), its Delaunay refinement into r.generation, and the crease
// counts; one log line per phase.
TetMeshOptions generate(const Case& c, const ImplicitFunction& body, const TetSizes& sizes,
                        const SizingFunction& size, const TetCaseOptions& options, TetCaseResult& r,
                        std::ostream& log) {
    Lap lap;
    TetMeshOptions mesh_options;
    mesh_options.size = size;
    mesh_options.facet_distance =
        c.tet_mesh.facet_distance > 0 ? c.tet_mesh.facet_distance : 0.1 * sizes.wall;
    std::string noise;
    CreaseCurves creases = body_creases(c, body, 0.5 * sizes.wall, noise);
    r.crease_polylines = Id(creases.polylines.size());
    r.corners = Id(creases.corners.size());
    mesh_options.features = std::move(creases.polylines);
    mesh_options.corners = std::move(creases.corners);
    mesh_options.cgal_sliver_removal = options.compare_cgal;
    mesh_options.cgal_sliver_bound = options.cgal_sliver_bound;
    mesh_options.cgal_time_limit = options.cgal_time_limit;
    r.seconds_features = lap();
    if (!noise.empty()) log << "creases: " << noise << "\n";
    log << fmt::format("creases: {} polylines, {} corners ({:.2f} s)\n", r.crease_polylines,
                       r.corners, r.seconds_features)
        << std::flush;

    r.generation = generate_tet_mesh(body, mesh_options);
    const PlacedTetMesh& refined = r.generation.refined;
    log << fmt::format("Delaunay refinement: {} tets, {} points ({:.2f} s)\n",
                       refined.mesh.num_cells(), refined.mesh.points.size(), r.generation.seconds);
    if (r.generation.cgal_optimized)
        log << fmt::format("CGAL perturb + exude: {:.2f} s\n", r.generation.cgal_seconds);
    log << std::flush;
    return mesh_options;
}

// r.cgal and its surface distance, of CGAL's perturbed and exuded mesh.
void measure_cgal(TetCaseResult& r, const BoundaryGeometry& boundary) {
    r.cgal = measure_tet_quality(r.generation.cgal_optimized->mesh);
    r.cgal_surface_distance = max_placed_distance(r.generation.cgal_optimized->mesh,
                                                  r.generation.cgal_optimized->dimension, boundary);
}

// What run_tet_case keeps: a mesh optimized by improve_tet_mesh (or CGAL's), and its quality.
struct Kept {
    Improved improved;
    TetQualityReport quality;
};

// CGAL's mesh optimized where that keeps its smallest angle (optimize_where_better), kept when
// it is at least as good as CGAL's mesh everywhere and better on the mean; else CGAL's mesh as
// it is. r.start says which.
void keep_cgal_mesh(const BoundaryGeometry& boundary, const SizingFunction& size,
                    const TetCaseOptions& options, TetCaseResult& r, Kept& kept,
                    std::ostream& log) {
    const PlacedTetMesh& cgal = *r.generation.cgal_optimized;
    // The bound: CGAL's smallest angle, and never one that leaves a sliver.
    const double bound = std::max(r.cgal->min_dihedral, r.cgal->sliver_degrees);
    HeldOptimization merged = optimize_where_better(cgal, bound, boundary, size, options);
    const double merged_distance = max_placed_distance(merged.mesh, cgal.dimension, boundary);
    const TetQualityReport merged_quality = measure_tet_quality(merged.mesh);
    Improved& k = kept.improved;
    k.caps_removed = k.flips_23 = k.edge_removals = k.points_inserted = 0;
    k.optimization.max_crease_distance = 0;
    const Id vertices = Id(cgal.mesh.points.size());
    log << fmt::format(
        "CGAL's mesh optimized, {} of its {} vertices held at their places: smallest angle "
        "{:.2f}, mean smallest {:.2f} degrees (CGAL's {:.2f}), {} slivers\n",
        merged.held, vertices, merged_quality.min_dihedral, merged_quality.mean_min_dihedral,
        r.cgal->mean_min_dihedral, merged_quality.slivers);
    if (merged.held < vertices && merged_quality.inverted == 0 &&
        merged_quality.min_dihedral >= r.cgal->min_dihedral &&
        merged_quality.slivers <= r.cgal->slivers &&
        merged_quality.mean_min_dihedral > r.cgal->mean_min_dihedral &&
        merged_distance <= r.cgal_surface_distance + 1e-9 * r.wall_size) {
        r.start = "CGAL's, optimized";
        r.cgal_vertices_held = merged.held;
        k.mesh = std::move(merged.mesh);
        k.optimization.solve = std::move(merged.optimization.solve);
        k.optimization.max_surface_distance = merged_distance;
        k.optimization.max_crease_distance = max_crease_distance(k.mesh, cgal.dimension, boundary);
        kept.quality = merged_quality;
    } else {
        r.start = "CGAL's";
        k.mesh = cgal.mesh;
        k.optimization.max_surface_distance = r.cgal_surface_distance;
        k.optimization.max_crease_distance = max_crease_distance(k.mesh, cgal.dimension, boundary);
        kept.quality = *r.cgal;
    }
}

// The last resort where the optimization of the refined mesh leaves slivers or ends under
// CGAL's own sliver removal: the same optimization started from CGAL's perturbed and exuded
// mesh (made now if it was not), and the best of the three meshes kept, said in the log.
void last_resort(const ImplicitFunction& body, TetMeshOptions& mesh_options,
                 const BoundaryGeometry& boundary, const SizingFunction& size,
                 const TetCaseOptions& options, TetCaseResult& r, Kept& kept, std::ostream& log) {
    const double ours = kept.quality.min_dihedral;
    if (!r.generation.cgal_optimized) {
        log << fmt::format(
                   "{} slivers left (smallest dihedral angle {:.2f} degrees): CGAL's perturb + "
                   "exude "
                   "of the refined mesh, to start from\n",
                   kept.quality.slivers, ours)
            << std::flush;
        mesh_options.cgal_sliver_removal = true;
        TetMeshGeneration again = generate_tet_mesh(body, mesh_options);
        r.generation.cgal_optimized = std::move(again.cgal_optimized);
        r.generation.cgal_seconds = again.cgal_seconds;
        measure_cgal(r, boundary);
    }
    Improved from_cgal =
        improve_tet_mesh(*r.generation.cgal_optimized, boundary, size, options, log);
    const TetQualityReport from_cgal_quality = measure_tet_quality(from_cgal.mesh);
    const double from_cgal_angle = from_cgal_quality.min_dihedral;
    if (from_cgal_angle > ours && from_cgal_angle >= r.cgal->min_dihedral) {
        r.start = "variational from CGAL's";
        kept.improved = std::move(from_cgal);
        kept.quality = from_cgal_quality;
    } else if (r.cgal->min_dihedral > ours) {
        keep_cgal_mesh(boundary, size, options, r, kept, log);
    }
    log << fmt::format(
               "smallest dihedral angle: variational {:.2f}, CGAL perturb+exude {:.2f}, "
               "variational "
               "from CGAL's {:.2f} degrees: kept {} ({:.2f})\n",
               ours, r.cgal->min_dihedral, from_cgal_angle, r.start, kept.quality.min_dihedral)
        << std::flush;
}

}  // namespace

TetCaseResult run_tet_case(const Case& c, const TetCaseOptions& options, std::ostream& log) {
    if (c.domain != Domain::interior)
        throw InputError(c.path +
                         ": domain: tetmesh meshes the body's interior (\"domain\": \"interior\")");
    TetCaseResult r;
    const std::shared_ptr<const ImplicitFunction> body = make_body(c.geometry);
    const TetSizes sizes = tet_sizes(c, *body);
    r.wall_size = sizes.wall;
    r.core_size = sizes.core;
    const SizingFunction size = tet_sizing(c, body);
    TetMeshOptions mesh_options = generate(c, *body, sizes, size, options, r, log);

    const BoundaryGeometry boundary = case_boundary(c, body, sizes.wall);
    const PlacedTetMesh& refined = r.generation.refined;
    r.refined = measure_tet_quality(refined.mesh);
    r.refined_surface_distance = max_placed_distance(refined.mesh, refined.dimension, boundary);
    if (r.generation.cgal_optimized) measure_cgal(r, boundary);

    Lap lap;
    Kept kept;
    kept.improved = improve_tet_mesh(refined, boundary, size, options, log);
    kept.quality = measure_tet_quality(kept.improved.mesh);
    if (kept.quality.slivers > 0 || (r.cgal && r.cgal->min_dihedral > kept.quality.min_dihedral))
        last_resort(*body, mesh_options, boundary, size, options, r, kept, log);
    r.mesh = std::move(kept.improved.mesh);
    r.optimization = std::move(kept.improved.optimization);
    r.caps_removed = kept.improved.caps_removed;
    r.flips_23 = kept.improved.flips_23;
    r.edge_removals = kept.improved.edge_removals;
    r.points_inserted = kept.improved.points_inserted;
    r.seconds_optimize = lap();
    r.optimized = kept.quality;
    return r;
}

void check_tet_outputs(const std::string& output, const std::string& cgal_output) {
    check_volume_mesh_output(output);
    if (cgal_output.empty()) return;
    check_volume_mesh_output(cgal_output);
    if (std::filesystem::weakly_canonical(cgal_output) == std::filesystem::weakly_canonical(output))
        throw std::invalid_argument("--cgal-output must differ from -o (" + output + ")");
}

std::vector<std::string> write_tet_case(const TetCaseResult& r, const Case& c,
                                        const std::string& output, const std::string& cgal_output,
                                        bool report, const std::string& title) {
    std::vector<std::string> written;
    write_volume_mesh(VolumeMesh{r.mesh.points, {}, r.mesh.tets, {}}, output);
    written.push_back(output);
    if (!cgal_output.empty()) {
        const TetMesh& m = r.generation.cgal_optimized->mesh;
        try {
            write_volume_mesh(VolumeMesh{m.points, {}, m.tets, {}}, cgal_output);
        } catch (...) {
            std::filesystem::remove(output);  // both or neither
            throw;
        }
        written.push_back(cgal_output);
    }
    if (report) {
        ReportPage page = tet_mesh_report_page(title, r.mesh, r.optimized);
        page.settings_json = case_to_json(c);
        page.peak_memory_bytes = peak_memory();
        written.push_back(write_report_beside(output, page));
    }
    return written;
}

std::string format_tet_comparison(const TetCaseResult& r) {
    const double h = r.wall_size;
    std::vector<TetQualityColumn> columns = {{"refined", &r.refined, r.refined_surface_distance / h,
                                              r.generation.seconds, std::nullopt}};
    if (r.cgal)
        columns.push_back({"CGAL perturb+exude", &*r.cgal, r.cgal_surface_distance / h,
                           r.generation.cgal_seconds, std::nullopt});
    columns.push_back({r.start, &r.optimized, r.optimization.max_surface_distance / h,
                       r.seconds_optimize, r.optimization.max_crease_distance / h});
    return format_tet_quality_table(columns);
}

}  // namespace hexmesh

#include "hexmesh/pipeline/tet_mesh_case.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/tet_report.h"
#include "surface/crease_curves.h"
#include "surface/sharp_features.h"
#include "untangle/tet_energy.h"
#include "volume/tet_flips.h"

namespace hexmesh {
namespace {

double elapsed(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Creases and corners for CGAL's feature protection: a surface file's sharp edges, or the
// creases of the implicit body traced at spacing `step`.
CreaseCurves body_creases(const Case& c, const ImplicitFunction& body, double step) {
    CreaseCurves curves;
    if (const auto surface = reference_surface(c.geometry)) {
        const FeatureCurves f = detect_sharp_features(*surface, {c.tet_mesh.feature_angle, true});
        for (const auto& chain : f.chains) {
            std::vector<Vec3> line;
            for (int id : chain) line.push_back(surface->points[id]);
            curves.polylines.push_back(std::move(line));
        }
        for (int id : f.corners) curves.corners.push_back(surface->points[id]);
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

// Per point: on a face of one tet.
std::vector<bool> on_boundary(const TetMesh& mesh) {
    static constexpr int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    std::unordered_map<std::array<Id, 3>, int, ArrayHash<Id, 3>> uses;
    for (Id t = 0; t < mesh.num_cells(); ++t)
        for (const auto& f : faces) {
            std::array<Id, 3> key = {mesh.node(t, f[0]), mesh.node(t, f[1]), mesh.node(t, f[2])};
            std::sort(key.begin(), key.end());
            ++uses[key];
        }
    std::vector<bool> boundary(mesh.points.size(), false);
    for (const auto& [key, count] : uses)
        if (count == 1)
            for (Id v : key) boundary[v] = true;
    return boundary;
}

}  // namespace

untangle::UntangleOptions tet_untangle_options() {
    untangle::UntangleOptions o;
    o.theta = 0.3;
    return o;
}

TetSizes tet_sizes(const Case& c, const ImplicitFunction& body) {
    TetSizes s;
    s.core = c.tet_mesh.cell_size > 0 ? c.tet_mesh.cell_size
             : c.grid.cell_size > 0   ? c.grid.cell_size
                                      : body.bounds().diagonal() / 30;
    s.wall = c.tet_mesh.wall_cell_size > 0 ? std::min(c.tet_mesh.wall_cell_size, s.core) : s.core;
    return s;
}

SizingFunction tet_sizing(const Case& c, std::shared_ptr<const ImplicitFunction> body) {
    const TetSizes s = tet_sizes(c, *body);
    if (s.wall >= s.core) return [core = s.core](const Vec3&) { return core; };
    return [s, grading = c.tet_mesh.grading, body](const Vec3& x) {
        return std::min(s.core, s.wall + grading * std::abs(body->value(x)));
    };
}

BoundaryGeometry case_boundary(const Case& c, std::shared_ptr<const ImplicitFunction> body,
                               double h) {
    if (auto surface = reference_surface(c.geometry))
        return BoundaryGeometry::triangles(*surface, c.tet_mesh.feature_angle, h);
    return BoundaryGeometry::implicit(std::move(body), h);
}

std::vector<VertexKind> kinds_from_dimensions(const std::vector<std::int8_t>& dimension) {
    std::vector<VertexKind> kinds(dimension.size());
    for (size_t v = 0; v < dimension.size(); ++v)
        kinds[v] = dimension[v] == 2   ? VertexKind::slip
                   : dimension[v] == 1 ? VertexKind::feature_edge
                   : dimension[v] == 0 ? VertexKind::corner
                                       : VertexKind::interior;
    return kinds;
}

std::vector<VertexKind> boundary_kinds(const TetMesh& mesh, const BoundaryGeometry& boundary,
                                       double reach) {
    const std::vector<bool> outer = on_boundary(mesh);
    std::vector<VertexKind> kinds(mesh.points.size(), VertexKind::interior);
    for (size_t v = 0; v < kinds.size(); ++v)
        if (outer[v]) kinds[v] = boundary.kind_at(mesh.points[v], reach);
    return kinds;
}

double max_boundary_distance(const TetMesh& mesh, const BoundaryGeometry& boundary) {
    const std::vector<bool> outer = on_boundary(mesh);
    double d = 0;
    for (size_t v = 0; v < outer.size(); ++v)
        if (outer[v]) d = std::max(d, boundary.surface_distance(mesh.points[v]));
    return d;
}

std::vector<untangle::TetTarget> sized_tet_targets(const std::vector<Vec3>& points,
                                                   const std::vector<Id>& tets,
                                                   const SizingFunction& size) {
    const Id cells = Id(tets.size() / 4);
    std::vector<double> edge(cells);
    double volume = 0, unsigned_volume = 0, target_volume = 0;
    for (Id t = 0; t < cells; ++t) {
        const Vec3 &a = points[tets[4 * t]], &b = points[tets[4 * t + 1]],
                   &c = points[tets[4 * t + 2]], &d = points[tets[4 * t + 3]];
        const double v = signed_volume({a, b, c, d});
        volume += v;
        unsigned_volume += std::abs(v);
        edge[t] = size(0.25 * (a + b + c + d));
        target_volume += std::pow(edge[t], 3) / (6 * std::sqrt(2.0));  // regular tet of that edge
    }
    if (!(volume > 0)) volume = unsigned_volume;  // folded beyond recognition: the best guess
    const double scale = target_volume > 0 ? std::cbrt(volume / target_volume) : 1;
    std::vector<untangle::TetTarget> targets(cells);
    for (Id t = 0; t < cells; ++t) targets[t] = untangle::regular_tet_target(scale * edge[t]);
    return targets;
}

TetOptimization optimize_tet_mesh(TetMesh& mesh, const std::vector<VertexKind>& kinds,
                                  const BoundaryGeometry& boundary, const SizingFunction& size,
                                  const untangle::UntangleOptions& options,
                                  const Reweighting& reweighting) {
    untangle::Problem p;
    p.kinds = kinds;
    p.points = mesh.points;
    const Id cells = mesh.num_cells();
    p.targets = sized_tet_targets(mesh.points, mesh.tets, size);
    p.tets.reserve(cells);
    double total_edge = 0;
    for (Id t = 0; t < cells; ++t) {
        p.tets.push_back({mesh.node(t, 0), mesh.node(t, 1), mesh.node(t, 2), mesh.node(t, 3)});
        total_edge += std::cbrt(6 * std::sqrt(2.0) * p.targets[t].weight);  // the target's edge
    }
    p.length_scale = cells > 0 ? total_edge / double(cells) : 1;
    for (size_t v = 0; v < p.points.size(); ++v)
        p.points[v] = boundary.place(p.points[v], kinds[v]);
    boundary.constrain(p);

    TetOptimization result;
    if (measure_tet_quality(TetMesh{p.points, mesh.tets}).inverted > 0) {
        // Tangled: untangle with the boundary held first (it lies on the surface already, and
        // a fixed boundary is the easier problem), then let it slip.
        untangle::Problem held = p;
        for (VertexKind& k : held.kinds)
            if (k != VertexKind::interior) k = VertexKind::fixed;
        untangle::UntangleOptions first = options;
        first.max_optimize_iterations = 0;
        result.solve = untangle::untangle_and_optimize(held, first);
        p.points = held.points;
    }
    {
        untangle::UntangleResult r = untangle::untangle_and_optimize(p, options);
        if (!result.solve.history.empty()) {  // report the tangled input as "before"
            r.inverted_before = result.solve.inverted_before;
            r.min_det_before = result.solve.min_det_before;
        }
        r.history.insert(r.history.begin(), result.solve.history.begin(),
                         result.solve.history.end());
        r.seconds += result.solve.seconds;
        result.solve = std::move(r);
    }
    // The sum of energies tolerates a few poor tets. Reweighting each by its own distortion,
    // w phi^(power - 1) (iteratively reweighted: towards the minimizer of sum w phi^power),
    // lifts the worst; the round with the largest smallest dihedral angle is kept.
    auto smallest_angle = [&] {
        double worst = 180;
        for (Id t = 0; t < cells; ++t) {
            const auto angles = dihedral_angles({p.points[p.tets[t][0]], p.points[p.tets[t][1]],
                                                 p.points[p.tets[t][2]], p.points[p.tets[t][3]]});
            worst = std::min(worst, *std::min_element(angles.begin(), angles.end()));
        }
        return worst;
    };
    const std::vector<untangle::TetTarget> base = p.targets;
    std::vector<Vec3> best = p.points;
    double best_angle = result.solve.inverted_after == 0 ? smallest_angle() : 0;
    for (int round = 0; round < reweighting.rounds && result.solve.inverted_after == 0; ++round) {
        const untangle::EnergyParams params{options.theta, 0};
        for (Id t = 0; t < cells; ++t) {
            const untangle::Mat34 y = untangle::Problem::corners(p.points, p.tets[t]);
            const double phi = untangle::tet_energy(y, base[t], params) / base[t].weight;
            p.targets[t].weight = base[t].weight * std::pow(phi, reweighting.power - 1);
        }
        const untangle::UntangleResult r = untangle::untangle_and_optimize(p, options);
        result.solve.history.insert(result.solve.history.end(), r.history.begin(), r.history.end());
        result.solve.seconds += r.seconds;
        if (r.inverted_after > 0) break;
        const double angle = smallest_angle();
        if (angle > best_angle) {
            best_angle = angle;
            best = p.points;
            result.solve.min_det_after = r.min_det_after;
        }
    }
    if (result.solve.inverted_after == 0) p.points = best;
    mesh.points = p.points;
    for (size_t v = 0; v < kinds.size(); ++v) {
        if (kinds[v] == VertexKind::interior || kinds[v] == VertexKind::fixed) continue;
        result.max_surface_distance =
            std::max(result.max_surface_distance, boundary.surface_distance(mesh.points[v]));
        if (kinds[v] != VertexKind::slip)
            result.max_crease_distance =
                std::max(result.max_crease_distance, boundary.crease_distance(mesh.points[v]));
    }
    return result;
}

Id keep_fallback_where_worse(const TetMesh& fallback, TetMesh& optimized, double bound) {
    std::vector<char> back(optimized.points.size(), 0);
    Id count = 0;
    for (bool changed = true; changed;) {
        changed = false;
        for (Id t = 0; t < optimized.num_cells(); ++t) {
            bool moved = false;
            for (int k = 0; k < 4; ++k) moved = moved || !back[optimized.node(t, k)];
            if (!moved) continue;
            const std::array<Vec3, 4> p = tet_corners(optimized, t);
            const auto angles = dihedral_angles(p);
            const bool same_side = signed_volume(p) * signed_volume(tet_corners(fallback, t)) > 0;
            if (same_side && *std::min_element(angles.begin(), angles.end()) >= bound) continue;
            for (int k = 0; k < 4; ++k) {
                const Id v = optimized.node(t, k);
                if (back[v]) continue;
                back[v] = 1, ++count, changed = true;
                optimized.points[v] = fallback.points[v];
            }
        }
    }
    return count;
}

namespace {

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
    Id caps_removed = 0, flips_23 = 0, edge_removals = 0;
};

// `start` with its boundary caps removed, optimized (optimize_tet_mesh), then cycles of flips
// and the optimization again, each kept while it raises the smallest dihedral angle.
Improved improve_tet_mesh(const PlacedTetMesh& start, const BoundaryGeometry& boundary,
                          const SizingFunction& size, const TetCaseOptions& options,
                          std::ostream& log) {
    Improved r;
    PlacedTetMesh work = start;
    r.caps_removed = options.cap_degrees > 0 ? remove_boundary_caps(work, options.cap_degrees) : 0;
    log << fmt::format("boundary caps removed: {}\n", r.caps_removed) << std::flush;
    r.mesh = std::move(work.mesh);
    const std::vector<VertexKind> kinds = kinds_from_dimensions(work.dimension);
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
    return r;
}

}  // namespace

TetCaseResult run_tet_case(const Case& c, const TetCaseOptions& options, std::ostream& log) {
    if (c.domain != "interior")
        throw InputError(c.path +
                         ": domain: tetmesh meshes the body's interior (\"domain\": \"interior\")");
    TetCaseResult r;
    const std::shared_ptr<const ImplicitFunction> body = make_body(c.geometry);
    const TetSizes sizes = tet_sizes(c, *body);
    r.wall_size = sizes.wall;
    r.core_size = sizes.core;
    const SizingFunction size = tet_sizing(c, body);

    auto start = std::chrono::steady_clock::now();
    TetMeshOptions mesh_options;
    mesh_options.size = size;
    mesh_options.facet_distance =
        c.tet_mesh.facet_distance > 0 ? c.tet_mesh.facet_distance : 0.1 * sizes.wall;
    CreaseCurves creases = body_creases(c, *body, 0.5 * sizes.wall);
    r.crease_polylines = Id(creases.polylines.size());
    r.corners = Id(creases.corners.size());
    mesh_options.features = std::move(creases.polylines);
    mesh_options.corners = std::move(creases.corners);
    mesh_options.cgal_sliver_removal = options.compare_cgal;
    mesh_options.cgal_sliver_bound = options.cgal_sliver_bound;
    mesh_options.cgal_time_limit = options.cgal_time_limit;
    r.seconds_features = elapsed(start);
    log << fmt::format("creases: {} polylines, {} corners ({:.2f} s)\n", r.crease_polylines,
                       r.corners, r.seconds_features)
        << std::flush;

    r.generation = generate_tet_mesh(*body, mesh_options);
    const PlacedTetMesh& refined = r.generation.refined;
    log << fmt::format("Delaunay refinement: {} tets, {} points ({:.2f} s)\n",
                       refined.mesh.num_cells(), refined.mesh.points.size(), r.generation.seconds);
    if (r.generation.cgal_optimized)
        log << fmt::format("CGAL perturb + exude: {:.2f} s\n", r.generation.cgal_seconds);
    log << std::flush;

    const BoundaryGeometry boundary = case_boundary(c, body, sizes.wall);
    r.refined = measure_tet_quality(refined.mesh);
    r.refined_surface_distance = max_placed_distance(refined.mesh, refined.dimension, boundary);
    if (r.generation.cgal_optimized) {
        r.cgal = measure_tet_quality(r.generation.cgal_optimized->mesh);
        r.cgal_surface_distance = max_placed_distance(
            r.generation.cgal_optimized->mesh, r.generation.cgal_optimized->dimension, boundary);
    }

    start = std::chrono::steady_clock::now();
    Improved kept = improve_tet_mesh(refined, boundary, size, options, log);
    TetQualityReport kept_quality = measure_tet_quality(kept.mesh);
    // The last resort where the optimization of the refined mesh leaves slivers or ends under
    // CGAL's own sliver removal: the same optimization started from CGAL's perturbed and
    // exuded mesh, and the best of the three meshes kept, said in the log.
    if (kept_quality.slivers > 0 || (r.cgal && r.cgal->min_dihedral > kept_quality.min_dihedral)) {
        const double ours = kept_quality.min_dihedral;
        if (!r.generation.cgal_optimized) {
            log << fmt::format(
                       "{} slivers left (smallest dihedral angle {:.2f} degrees): CGAL's perturb + "
                       "exude "
                       "of the refined mesh, to start from\n",
                       kept_quality.slivers, ours)
                << std::flush;
            mesh_options.cgal_sliver_removal = true;
            TetMeshGeneration again = generate_tet_mesh(*body, mesh_options);
            r.generation.cgal_optimized = std::move(again.cgal_optimized);
            r.generation.cgal_seconds = again.cgal_seconds;
            r.cgal = measure_tet_quality(r.generation.cgal_optimized->mesh);
            r.cgal_surface_distance =
                max_placed_distance(r.generation.cgal_optimized->mesh,
                                    r.generation.cgal_optimized->dimension, boundary);
        }
        Improved from_cgal =
            improve_tet_mesh(*r.generation.cgal_optimized, boundary, size, options, log);
        const TetQualityReport from_cgal_quality = measure_tet_quality(from_cgal.mesh);
        const double from_cgal_angle = from_cgal_quality.min_dihedral;
        if (from_cgal_angle > ours && from_cgal_angle >= r.cgal->min_dihedral) {
            r.start = "variational from CGAL's";
            kept = std::move(from_cgal);
            kept_quality = from_cgal_quality;
        } else if (r.cgal->min_dihedral > ours) {
            // CGAL's mesh optimized where that keeps its smallest angle, else as it is.
            const PlacedTetMesh& cgal = *r.generation.cgal_optimized;
            // The bound: CGAL's smallest angle, and never one that leaves a sliver.
            const double bound = std::max(r.cgal->min_dihedral, r.cgal->sliver_degrees);
            HeldOptimization merged = optimize_where_better(cgal, bound, boundary, size, options);
            const double merged_distance =
                max_placed_distance(merged.mesh, cgal.dimension, boundary);
            const TetQualityReport merged_quality = measure_tet_quality(merged.mesh);
            kept.caps_removed = kept.flips_23 = kept.edge_removals = 0;
            kept.optimization.max_crease_distance =
                std::numeric_limits<double>::quiet_NaN();  // not measured
            const Id vertices = Id(cgal.mesh.points.size());
            log << fmt::format(
                "CGAL's mesh optimized, {} of its {} vertices held at their places: smallest angle "
                "{:.2f}, mean smallest {:.2f} degrees (CGAL's {:.2f}), {} slivers\n",
                merged.held, vertices, merged_quality.min_dihedral,
                merged_quality.mean_min_dihedral, r.cgal->mean_min_dihedral,
                merged_quality.slivers);
            if (merged.held < vertices && merged_quality.inverted == 0 &&
                merged_quality.min_dihedral >= r.cgal->min_dihedral &&
                merged_quality.slivers <= r.cgal->slivers &&
                merged_quality.mean_min_dihedral > r.cgal->mean_min_dihedral &&
                merged_distance <= r.cgal_surface_distance + 1e-9 * r.wall_size) {
                r.start = "CGAL's, optimized";
                r.cgal_vertices_held = merged.held;
                kept.mesh = std::move(merged.mesh);
                kept.optimization.solve = std::move(merged.optimization.solve);
                kept.optimization.max_surface_distance = merged_distance;
                kept_quality = merged_quality;
            } else {
                r.start = "CGAL's";
                kept.mesh = cgal.mesh;
                kept.optimization.max_surface_distance = r.cgal_surface_distance;
                kept_quality = *r.cgal;
            }
        }
        log << fmt::format(
                   "smallest dihedral angle: variational {:.2f}, CGAL perturb+exude {:.2f}, "
                   "variational "
                   "from CGAL's {:.2f} degrees: kept {} ({:.2f})\n",
                   ours, r.cgal->min_dihedral, from_cgal_angle, r.start, kept_quality.min_dihedral)
            << std::flush;
    }
    r.mesh = std::move(kept.mesh);
    r.optimization = std::move(kept.optimization);
    r.caps_removed = kept.caps_removed;
    r.flips_23 = kept.flips_23;
    r.edge_removals = kept.edge_removals;
    r.seconds_optimize = elapsed(start);
    r.optimized = kept_quality;
    return r;
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

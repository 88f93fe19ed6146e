#include "hexmesh/pipeline/optimize_tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/validity.h"
#include "untangle/tet_energy.h"

namespace hexmesh {
namespace {

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

// The problem of `mesh`: its tets with the targets of sized_tet_targets, every boundary vertex
// placed on the part of the surface its kind names, and the boundary's constraints.
untangle::Problem tet_problem(const TetMesh& mesh, const std::vector<VertexKind>& kinds,
                              const BoundaryGeometry& boundary, const SizingFunction& size) {
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
    return p;
}

// Untangles and optimizes `p` (tets: the mesh's point ids, 4 per tet). Tangled: untangled with
// the boundary held first (it lies on the surface already, and a fixed boundary is the easier
// problem), then let slip; the result reports the tangled input as "before".
untangle::UntangleResult untangle_then_optimize(untangle::Problem& p, const std::vector<Id>& tets,
                                                const untangle::UntangleOptions& options) {
    untangle::UntangleResult first_pass;
    if (measure_tet_quality(TetMesh{p.points, tets}).inverted > 0) {
        untangle::Problem held = p;
        for (VertexKind& k : held.kinds)
            if (k != VertexKind::interior) k = VertexKind::fixed;
        untangle::UntangleOptions first = options;
        first.max_optimize_iterations = 0;
        first_pass = untangle::untangle_and_optimize(held, first);
        p.points = held.points;
    }
    untangle::UntangleResult r = untangle::untangle_and_optimize(p, options);
    if (!first_pass.history.empty()) {
        r.inverted_before = first_pass.inverted_before;
        r.min_det_before = first_pass.min_det_before;
    }
    r.history.insert(r.history.begin(), first_pass.history.begin(), first_pass.history.end());
    r.seconds += first_pass.seconds;
    return r;
}

// The smallest dihedral angle of `p`'s tets, in degrees.
double smallest_angle(const untangle::Problem& p) {
    double worst = 180;
    for (const auto& t : p.tets) {
        const auto angles =
            dihedral_angles({p.points[t[0]], p.points[t[1]], p.points[t[2]], p.points[t[3]]});
        worst = std::min(worst, *std::min_element(angles.begin(), angles.end()));
    }
    return worst;
}

// The sum of energies tolerates a few poor tets. Reweighting each by its own distortion,
// w phi^(power - 1) (iteratively reweighted: towards the minimizer of sum w phi^power),
// lifts the worst; the round with the largest smallest dihedral angle is kept in p.points.
// `solve` (of the plain minimization) gets the rounds' history and time.
void reweight(untangle::Problem& p, const untangle::UntangleOptions& options,
              const Reweighting& reweighting, untangle::UntangleResult& solve) {
    const Id cells = Id(p.tets.size());
    const std::vector<untangle::TetTarget> base = p.targets;
    std::vector<Vec3> best = p.points;
    double best_angle = solve.inverted_after == 0 ? smallest_angle(p) : 0;
    for (int round = 0; round < reweighting.rounds && solve.inverted_after == 0; ++round) {
        const untangle::EnergyParams params{options.theta, 0};
        for (Id t = 0; t < cells; ++t) {
            const untangle::Mat34 y = untangle::Problem::corners(p.points, p.tets[t]);
            const double phi = untangle::tet_energy(y, base[t], params) / base[t].weight;
            p.targets[t].weight = base[t].weight * std::pow(phi, reweighting.power - 1);
        }
        const untangle::UntangleResult r = untangle::untangle_and_optimize(p, options);
        solve.history.insert(solve.history.end(), r.history.begin(), r.history.end());
        solve.seconds += r.seconds;
        if (r.inverted_after > 0) break;
        const double angle = smallest_angle(p);
        if (angle > best_angle) {
            best_angle = angle;
            best = p.points;
            solve.min_det_after = r.min_det_after;
        }
    }
    if (solve.inverted_after == 0) p.points = best;
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

FeatureOptions tet_crease_options(const Case& c) {
    FeatureOptions o;
    o.angle_degrees = c.tet_mesh.feature_angle;
    o.include_boundary = true;
    o.noise_ratio = facet_noise_ratio;
    return o;
}

BoundaryGeometry case_boundary(const Case& c, std::shared_ptr<const ImplicitFunction> body,
                               double h) {
    if (auto surface = reference_surface(c.geometry))
        return BoundaryGeometry::triangles(*surface, tet_crease_options(c), h);
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
    untangle::Problem p = tet_problem(mesh, kinds, boundary, size);
    TetOptimization result;
    result.solve = untangle_then_optimize(p, mesh.tets, options);
    reweight(p, options, reweighting, result.solve);
    mesh.points = p.points;
    measure_boundary_distances(mesh, kinds, boundary, result);
    return result;
}

void measure_boundary_distances(const TetMesh& mesh, const std::vector<VertexKind>& kinds,
                                const BoundaryGeometry& boundary, TetOptimization& result) {
    result.max_surface_distance = result.max_crease_distance = 0;
    for (size_t v = 0; v < kinds.size(); ++v) {
        if (kinds[v] == VertexKind::interior || kinds[v] == VertexKind::fixed) continue;
        result.max_surface_distance =
            std::max(result.max_surface_distance, boundary.surface_distance(mesh.points[v]));
        if (kinds[v] != VertexKind::slip)
            result.max_crease_distance =
                std::max(result.max_crease_distance, boundary.crease_distance(mesh.points[v]));
    }
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

Id raise_smallest_angles(TetMesh& mesh, const std::vector<VertexKind>& kinds,
                         const BoundaryGeometry& boundary, double below_degrees, int passes) {
    std::vector<std::vector<Id>> star(mesh.points.size());
    for (Id t = 0; t < mesh.num_cells(); ++t)
        for (int k = 0; k < 4; ++k) star[mesh.node(t, k)].push_back(t);
    // The smallest angle of the tets around v with v at y, or -1 if one is not positive.
    auto star_angle = [&](Id v, const Vec3& y) {
        const Vec3 old = mesh.points[v];
        mesh.points[v] = y;
        double angle = 180;
        for (Id t : star[v]) {
            const std::array<Vec3, 4> p = tet_corners(mesh, t);
            if (exact_orientation(p[0], p[1], p[2], p[3]) <= 0) {
                angle = -1;
                break;
            }
            angle = std::min(angle, smallest_dihedral_angle(p));
        }
        mesh.points[v] = old;
        return angle;
    };
    std::vector<Vec3> space;  // the 6 axes and 8 diagonals, for interior points
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k)
                if ((i || j || k) && std::abs(i) + std::abs(j) + std::abs(k) != 2)
                    space.push_back(Vec3(i, j, k).normalized());
    // The directions a point of kind `kind` at x tries: in space, in the surface's tangent
    // plane (8), or along its crease (2).
    auto directions = [&](VertexKind kind, const Vec3& x) {
        if (kind == VertexKind::feature_edge) {
            const Vec3 t = boundary.crease_direction(x).normalized();
            return std::vector<Vec3>{t, -t};
        }
        if (kind != VertexKind::slip) return space;
        const Vec3 n = boundary.surface_normal(x).normalized();
        if (!(n.norm() > 0.5)) return std::vector<Vec3>{};  // no normal there: the point stays
        const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
        const double eighth = std::acos(-1.0) / 4;
        std::vector<Vec3> plane;
        for (int k = 0; k < 8; ++k)
            plane.push_back(std::cos(k * eighth) * u + std::sin(k * eighth) * w);
        return plane;
    };
    Id moves = 0;
    // A point whose search found nothing is searched again only after a point of a tet around
    // it has moved.
    std::vector<char> stuck(mesh.points.size(), 0);
    for (int pass = 0; pass < passes; ++pass) {
        std::vector<std::pair<double, Id>> poor;
        for (Id t = 0; t < mesh.num_cells(); ++t) {
            const double angle = smallest_dihedral_angle(tet_corners(mesh, t));
            if (angle < below_degrees) poor.push_back({angle, t});
        }
        std::sort(poor.begin(), poor.end());
        Id moved_in_pass = 0;
        for (const auto& [angle, t] : poor)
            for (int k = 0; k < 4; ++k) {
                const Id v = mesh.node(t, k);
                if (kinds[v] == VertexKind::fixed || kinds[v] == VertexKind::corner || stuck[v])
                    continue;
                double shortest = INFINITY;
                for (Id s : star[v])
                    for (int m = 0; m < 4; ++m)
                        if (mesh.node(s, m) != v)
                            shortest = std::min(
                                shortest, (mesh.points[mesh.node(s, m)] - mesh.points[v]).norm());
                double best = star_angle(v, mesh.points[v]);
                Vec3 best_point = mesh.points[v];
                std::vector<Vec3> tried = directions(kinds[v], best_point);
                bool moved = false;
                // Until the tets around v reach the bound: beyond it, a move would only
                // change tets that need nothing. A step is judged in the tangent plane or
                // line first, then again once placed back on the boundary.
                for (double step = 0.2 * shortest;
                     step > 1e-2 * shortest && best < below_degrees;) {
                    bool better = false;
                    for (const Vec3& d : tried) {
                        if (!(star_angle(v, best_point + step * d) > best + 1e-9)) continue;
                        const Vec3 y = boundary.place(best_point + step * d, kinds[v]);
                        const double q = star_angle(v, y);
                        if (q > best + 1e-9) {
                            best = q, best_point = y, better = true;
                            break;
                        }
                    }
                    if (better && kinds[v] != VertexKind::interior)
                        tried = directions(kinds[v], best_point);
                    if (!better) step *= 0.5;
                    moved |= better;
                }
                stuck[v] = !moved;
                if (!moved) continue;
                mesh.points[v] = best_point, ++moved_in_pass;
                for (Id s : star[v])
                    for (int m = 0; m < 4; ++m)
                        if (mesh.node(s, m) != v) stuck[mesh.node(s, m)] = 0;
            }
        moves += moved_in_pass;
        if (moved_in_pass == 0) break;
    }
    return moves;
}

}  // namespace hexmesh

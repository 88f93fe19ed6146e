#include "hexmesh/pipeline/untangle_and_optimize.h"

#include <fmt/format.h>

#include <algorithm>

#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/pipeline/lay_boundary_layer.h"
#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/mend_cells.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// The joint untangling and optimization of the whole grid (see optimize_grid). With layers,
// inverted elements all at the wall or its layers are left to the layer pass, which lays the
// layers again and frees them in seconds where the continuation's restarts and last resorts
// took minutes (the bull outside: 2 elements, freed by the layer pass).
untangle::UntangleResult joint_pass(BlockGrid& grid, const ImplicitFunction& body,
                                    const GridOptimizationOptions& options,
                                    const std::vector<bool>& shaped) {
    GridProblem g = corner_tet_problem(grid, grid.points, body, options.held, shaped);
    hold_wall_quads(grid, grid.points, body, options.wall_fidelity, g);
    untangle::UntangleOptions joint = options.untangle;
    joint.local_rounds = options.local_rounds;
    if (options.wall_layers.layers > 0) {
        joint.leave_to_next_pass = [&g, near = wall_layer_nodes(grid, options.wall_layers.layers)](
                                       const std::vector<Vec3>& x) {
            return g.inverted_all_touch(x, near);
        };
    }
    const untangle::UntangleResult r = untangle::untangle_and_optimize(g.problem, joint);
    g.scatter(grid.points);
    return r;
}

// How a grid ranks in the polish: fewer cells and faces a solver refuses (inverted, or failing
// checkMesh's cell and face checks: QualityReport::refused_count), then a higher worst scaled
// Jacobian, then fewer cells under the polish threshold (the worst cell may be one the polish
// holds).
struct PolishRank {
    Id refused = 0;
    double min_sj = 0;
    Id below = 0;
    // `sj`: the grid's scaled Jacobians (scaled_jacobians).
    PolishRank(const BlockGrid& grid, const std::vector<double>& sj, double threshold) {
        const QualityReport q = measure_quality(grid);
        refused = q.refused_count();
        min_sj = q.min_scaled_jacobian;
        below =
            Id(std::count_if(sj.begin(), sj.end(), [&](double v) { return !(v >= threshold); }));
    }
    bool better_than(const PolishRank& o) const {
        if (refused != o.refused) return refused < o.refused;
        if (min_sj != o.min_sj) return min_sj > o.min_sj;
        return below < o.below;
    }
};

// The layer pass's outcome, for the run's log.
void log_layer_pass(const GridOptimizationResult& r, int layers, std::ostream& log) {
    if (r.layers_skipped) {
        log << fmt::format(
            "  boundary layer not laid again: the joint optimization left {} inverted "
            "elements, some away "
            "from the wall and its layers\n",
            r.solve.inverted_after);
    } else if (layers > 0 && r.laid_nodes == 0) {
        log << "  boundary layer kept as built (no wall-normal line can be laid alone)\n";
    } else if (r.layers_blocked > 0) {
        log << fmt::format(
            "  boundary layer laid along the wall normals crosses the grid ({} corner tets "
            "inverted between held nodes): the joint optimization's grid is kept\n",
            r.layers_blocked);
    } else if (layers > 0) {
        log << "  boundary layer laid along the wall normals"
            << (r.lines_given_back > 0 ? fmt::format(" (but on {} wall lines, whose laid cells "
                                                     "would cross or fall under half "
                                                     "the worst scaled Jacobian before: they "
                                                     "keep the joint optimization's)",
                                                     r.lines_given_back)
                                       : std::string())
            << ", rest optimized again:\n"
            << untangle::format_untangle_summary(r.layers_held);
        if (!r.layers_laid)
            log << "  the laid layers left inverted cells: the joint optimization's grid is "
                   "kept\n";
    }
}

// The cells a solver refuses mended node by node (hexmesh/pipeline/mend_cells.h), one line
// to `log`; the cells still refused.
Id mend(BlockGrid& grid, const ImplicitFunction& body, std::ostream& log) {
    const MendResult m = mend_refused_cells(grid, body);
    log << fmt::format(
        "  cells a solver refuses mended node by node (the solver's own checks): {} -> {}, "
        "smallest margin {:.3g} -> {:.3g} ({} moves)\n",
        m.refused_before, m.refused_after, m.min_margin_before, m.min_margin_after, m.moves);
    return m.refused_after;
}

// One line for a polish pass that had cells to polish.
void log_polish_pass(const PolishOptions& o, const PolishResult& r, std::ostream& log) {
    if (o.refused_only)
        log << fmt::format(
            "  cells a solver refuses (checkMesh's cell checks) and {} rings around them, "
            "layers free: {} -> {}",
            o.rings, r.refused_before, r.refused_after);
    else
        log << fmt::format(
            "  worst cells polished{}: {} -> {} cells with a scaled Jacobian under {}",
            o.held.empty() ? ", layers free" : " beyond the boundary layer", r.cells, r.cells_after,
            o.below);
    log << fmt::format(", min scaled Jacobian {:.3g} -> {:.3g} ({} rounds, {:.2f} s)\n",
                       r.min_sj_before, r.min_sj_after, r.rounds, r.seconds);
}

// The worst cells optimized again in their neighbourhood (polish_worst_cells), the wall and
// its boundary layer held. While the grid then has cells a solver refuses: they are mended node
// by node (mend); what is left, with 2, 4, then 8 rings around them, layers free (validity
// before the layers' spacing); then every cell under the threshold, layers free; then mended
// again. One line per pass.
void polish_passes(Job& job) {
    BlockGrid& grid = job.grid();
    PolishOptions o;
    o.untangle = job.solver_options();
    o.untangle.log = nullptr;              // a summary line instead
    o.untangle.optimize_tolerance = 1e-7;  // a small problem: its worst cells weigh
    o.untangle.max_optimize_iterations = 50;
    o.wall_fidelity = job.settings.solver.wall_fidelity;
    const int layers = wall_layers(job.settings).layers;
    if (layers > 0) o.held = wall_layer_nodes(grid, layers);
    for (int pass = 0; pass < 5; ++pass) {
        const PolishResult r = polish_worst_cells(grid, *job.body, o);
        if (r.cells > 0) log_polish_pass(o, r, job.log);
        if (r.refused_after == 0) return;
        // A face warped past its cell's centre, which the corner tets do not see: the nodes of
        // such cells moved one by one, before the layers around them are let go.
        if (pass == 0 && mend(grid, *job.body, job.log) == 0) return;
        o.held.clear();
        o.refused_only = pass < 3;  // rings 2, 4, 8; then every cell under the threshold, rings 2
        o.rings = pass < 3 ? 2 << pass : 2;
    }
    mend(grid, *job.body, job.log);
}

// Each wall node's line through the boundary layer (nodes 0 .. layers), once, from the wall
// faces deeper than the layers.
std::vector<std::vector<Id>> layer_lines(const BlockGrid& grid, int layers) {
    std::vector<std::vector<Id>> lines;
    std::vector<bool> seen(grid.points.size(), false);
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                if (f.depth <= layers || seen[f.node(p, q, 0)]) continue;
                seen[f.node(p, q, 0)] = true;
                std::vector<Id> line;
                for (int t = 0; t <= layers; ++t) line.push_back(f.node(p, q, t));
                lines.push_back(std::move(line));
            }
    return lines;
}

// The polish (polish_passes), then the worst cells lifted node by node (lift_worst_cells), the
// boundary layer's nodes each on its own level of u, and its lines also moved whole, the
// far field's nodes on its sphere. One line per pass.
void polish(Job& job) {
    BlockGrid& grid = job.grid();
    // Cells the joint untangling left inverted are not repaired by a local optimization (it
    // runs the same continuation): the grid goes to its refusal as it is.
    if (const Id inverted = measure_quality(grid).inverted_cells; inverted > 0) {
        job.log << fmt::format("  no polish: {} cells are still inverted\n", inverted);
        return;
    }
    polish_passes(job);
    LiftOptions o;
    if (const int layers = wall_layers(job.settings).layers; layers > 0) {
        o.on_level = wall_layer_nodes(grid, layers);
        o.lines = layer_lines(grid, layers);
    }
    const std::optional<Sphere> far = far_field_sphere(grid, o.on_far);
    if (far) o.far = &*far;
    const LiftResult r = lift_worst_cells(grid, *job.body, o);
    if (r.cells_before > 0)
        job.log << fmt::format(
            "  worst cells lifted node by node, layers on their levels: {} -> {} cells with a "
            "scaled Jacobian under {}, min scaled Jacobian {:.3g} -> {:.3g} ({} moves, {} of whole "
            "lines; {} steps of the worst cells' nodes together)\n",
            r.cells_before, r.cells_after, o.below, r.min_sj_before, r.min_sj_after, r.moves,
            r.line_moves, r.joint_steps);
    // Lines the layer pass gave back keep the joint optimization's layer nodes, and the lift
    // moves lines whole: the heights restored last, where the cells around allow.
    if (const WallLayers law = wall_layers(job.settings); law.layers > 0) {
        const LayerHeightsResult h = restore_layer_heights(grid, *job.body, law);
        if (h.lines > 0)
            job.log << fmt::format(
                "  boundary layer heights restored where the cells allow: {} of {} lines off "
                "the law's heights moved (first layer within 10 % on {} -> {} of them)\n",
                h.moved, h.lines, h.within_before, h.within_after);
    }
}

}  // namespace

GridOptimizationResult optimize_grid(BlockGrid& grid, const ImplicitFunction& body,
                                     const GridOptimizationOptions& options) {
    GridOptimizationResult result;
    const int layers = options.wall_layers.layers;
    // The targets of both passes: the grid as given (kept aside only when a second pass needs it).
    const std::vector<Vec3> initial = layers > 0 ? grid.points : std::vector<Vec3>{};
    // The nodes whose cells keep their shapes in both passes: the crease lines' nodes up to
    // layers + 1 (the laid layers' cells and the two beyond), found once on the grid as given.
    const std::vector<bool> shaped = options.keep_crease_shapes
                                         ? crease_line_nodes(grid, body, layers + 1)
                                         : std::vector<bool>{};
    result.solve = joint_pass(grid, body, options, shaped);
    result.untangling_work = result.solve.work;
    // Laying the layers again moves the wall's layer nodes and optimizes the cells around them
    // and around the poor ones: it can free inverted elements the joint pass left at the wall
    // (the bull outside). On every run measured it freed none that the joint pass left away
    // from the wall and its layers, and took up to minutes there (bench/RESULTS.md): skipped.
    result.layers_skipped =
        layers > 0 && result.solve.inverted_after > 0 && inverted_away_from_layers(grid, layers);
    if (layers > 0 && !result.layers_skipped)
        lay_boundary_layer(grid, body, options, initial, shaped, result);
    return result;
}

PolishResult polish_worst_cells(BlockGrid& grid, const ImplicitFunction& body,
                                const PolishOptions& options) {
    PolishResult result;
    std::vector<double> sj = scaled_jacobians(grid);
    const PolishRank first(grid, sj, options.below);
    result.min_sj_before = result.min_sj_after = first.min_sj;
    result.refused_before = result.refused_after = first.refused;
    // The cells to polish, in for_each_cell order over the blocks (`sj` of the grid as it is).
    const auto to_polish = [&] {
        std::vector<bool> cells(size_t(grid.num_cells()), false);
        if (options.refused_only) {
            for (Id c : find_refused_cells(to_hex_mesh(grid))) cells[c] = true;
        } else {
            for (size_t c = 0; c < sj.size(); ++c) cells[c] = !(sj[c] >= options.below);
        }
        return cells;
    };
    std::vector<bool> cells = to_polish();
    result.cells = result.cells_after = Id(std::count(cells.begin(), cells.end(), true));
    std::vector<Vec3> best = grid.points;
    PolishRank best_rank = first;
    for (int round = 0; round < options.rounds && std::count(cells.begin(), cells.end(), true) > 0;
         ++round) {
        std::vector<bool> marked(grid.points.size(), false);
        size_t c = 0;
        for (const Block& block : grid.blocks)
            for_each_cell(block, [&](int, int, int, const std::array<Id, 8>& nodes) {
                if (cells[c++])
                    for (Id v : nodes) marked[v] = true;
            });
        std::vector<bool> held = grow_by_cells(grid, marked, options.rings);
        held.flip();
        if (!options.held.empty())
            for (size_t v = 0; v < held.size(); ++v) held[v] = held[v] || options.held[v];
        GridProblem g = corner_tet_problem(grid, grid.points, body, held, {});
        if (g.nodes.empty()) break;  // every node of those cells held (the wall and its layers)
        hold_wall_quads(grid, grid.points, body, options.wall_fidelity, g);
        const untangle::UntangleResult r =
            untangle::untangle_and_optimize(g.problem, options.untangle);
        ++result.rounds;
        result.seconds += r.seconds;
        if (r.inverted_after > 0) break;  // the next round would start from worse
        g.scatter(grid.points);  // the next round starts here, even if this one ranks lower
        sj = scaled_jacobians(grid);
        cells = to_polish();
        const PolishRank rank(grid, sj, options.below);
        if (rank.better_than(best_rank)) {
            best = grid.points, best_rank = rank;
            result.cells_after = Id(std::count(cells.begin(), cells.end(), true));
        }
    }
    grid.points = std::move(best);
    result.min_sj_after = best_rank.min_sj;
    result.refused_after = best_rank.refused;
    return result;
}

void untangle_and_optimize(Job& job) {
    const Case& c = job.settings;
    GridOptimizationOptions o;
    o.untangle = job.solver_options();
    o.wall_layers = wall_layers(c);
    o.keep_crease_shapes = c.domain == Domain::exterior;  // its lines leave creases mitred
    o.wall_fidelity = c.solver.wall_fidelity;
    // Every corner tet weighs the same while untangling (joint pass and layer pass), unless a
    // retry says otherwise: weighed by volume, the first layer's inversions hardly count against
    // the far field's or the core's cells (1e7 times theirs outside, 1e3 inside).
    o.untangle.equal_weights = !job.volume_weights;
    o.untangle.max_work = job.work_budget;
    // Outside a body that is not star-shaped, a grid along the potential's gradient lines that
    // stays tangled is made again along the fibres (run_case.cpp, retry_with_fibres): its
    // untangling tries two neighbourhood sizes and hands over instead of going on with the
    // larger ones and the last resorts, which on the shared bodies freed none of what the two
    // left (the hand and homer outside spent 30-40 s there before the fibres made them valid).
    if (c.domain == Domain::exterior && job.route.along_first_lines()) o.local_rounds = 2;
    const GridOptimizationResult r = optimize_grid(job.grid(), *job.body, o);
    // Whether the weights counted in the grid kept: the joint pass untangled, or the layer pass
    // whose laid layers the grid keeps did.
    job.untangled = r.solve.inverted_before > 0 || (r.layers_laid && r.layers_untangled);
    job.untangling_work = r.untangling_work;
    note_wall_miss(job, "after the volume passes");
    job.log << untangle::format_untangle_summary(r.solve);
    log_layer_pass(r, o.wall_layers.layers, job.log);
    job.timer.done("optimization");
    polish(job);
    job.timer.done("polish");
}

}  // namespace hexmesh

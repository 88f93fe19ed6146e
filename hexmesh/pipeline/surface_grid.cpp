#include "hexmesh/pipeline/surface_grid.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>

#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/pipeline/measure.h"
#include "hexmesh/quality/cell_quality.h"
#include "volume/feature_snapping.h"
#include "volume/tfi.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

// The wall grid of `faces` as a problem of surface triangles: `nodes` maps problem ids to
// grid ids. Each quad's corner triangles turn counter-clockwise seen from where grad u
// points (the face's orientation taken from the majority of its quads). With fidelity > 0
// each quad is also held to u = 0 (untangle::HeldQuad): fidelity 2 a b (u(c) / sqrt(a b))^2,
// its corner triangles' best energy (2 a b) times its centre's distance to the body in
// its own size.
struct SurfaceProblem {
    untangle::Problem problem;
    std::vector<Id> nodes;
};

SurfaceProblem make_surface_problem(const BlockGrid& grid, const std::vector<WallFace>& faces,
                                    const ImplicitFunction& body, double fidelity) {
    SurfaceProblem s;
    untangle::Problem& p = s.problem;
    std::vector<Id> local(grid.points.size(), -1);
    const auto local_id = [&](Id v) {
        if (local[v] < 0) {
            local[v] = Id(s.nodes.size());
            s.nodes.push_back(v);
            p.points.push_back(grid.points[v]);
            p.kinds.push_back(grid.kinds[v]);
        }
        return local[v];
    };
    double total = 0;
    for (const WallFace& f : faces) {
        // Quad (p, q): its corners in cyclic order.
        const auto quad = [&f](int a, int b) {
            return std::array<Id, 4>{f.node(a, b, 0), f.node(a + 1, b, 0), f.node(a + 1, b + 1, 0),
                                     f.node(a, b + 1, 0)};
        };
        double turn = 0;
        for (int b = 0; b + 1 < f.nq; ++b)
            for (int a = 0; a + 1 < f.np; ++a) {
                const auto q = quad(a, b);
                const Vec3& x0 = grid.points[q[0]];
                const Vec3 n = body.gradient(x0);
                const double d = n.dot((grid.points[q[1]] - x0).cross(grid.points[q[3]] - x0));
                turn += (d > 0) - (d < 0);
            }
        for (int b = 0; b + 1 < f.nq; ++b)
            for (int a = 0; a + 1 < f.np; ++a) {
                std::array<Id, 4> q = quad(a, b);
                if (turn < 0) std::swap(q[1], q[3]);
                const auto length = [&](int c, int d) {
                    return (grid.points[q[c]] - grid.points[q[d]]).norm();
                };
                // Mean lengths of the two pairs of opposite edges: (0-1, 3-2) and (0-3, 1-2).
                const double first = (length(0, 1) + length(3, 2)) / 2,
                             second = (length(0, 3) + length(1, 2)) / 2;
                total += first + second;
                // Local ids in the order the quad's corner triangles first meet its nodes.
                const Id n0 = local_id(q[0]), n1 = local_id(q[1]), n3 = local_id(q[3]),
                         n2 = local_id(q[2]);
                p.add_quad({n0, n1, n2, n3}, first, second);
                if (fidelity > 0)
                    p.held_quads.push_back({{n0, n1, n2, n3}, 2 * fidelity, 2 * fidelity});
            }
    }
    const size_t quads = p.triangles.size() / 4;
    p.length_scale = quads > 0 ? total / (2.0 * double(quads)) : 1.0;
    slide_on(body, p);
    if (!p.held_quads.empty()) p.surface_value = [&body](const Vec3& x) { return body.value(x); };
    return s;
}

// Cells whose scaled Jacobian (corners and centre) is <= 0.
Id nonpositive_cells(const BlockGrid& grid) {
    const std::vector<double> sj = scaled_jacobians(grid);
    return Id(std::count_if(sj.begin(), sj.end(), [](double q) { return !(q > 0); }));
}

// The surface pass, then the volume from the optimized wall (see make_surface_grid).
void surface_pass(Job& job) {
    const Case& c = job.settings;
    BlockGrid& grid = job.grid();
    untangle::UntangleOptions surface = job.solver_options();
    surface.max_optimize_iterations = c.solver.surface_iterations;
    // Folds that three rounds of local repair (2, 4 and 8 rings) leave are left to the volume
    // passes, without the global pass and the restarts from eps 0.1: on the shared bodies those
    // freed none of them (NACA0012's 40 triangles folded over its trailing edge, homer's 7, the
    // spool's 49) and took 1-3 s of each surface pass; the bull inside frees its last one in
    // the third round.
    surface.local_rounds = 3;
    job.log << "  surface grid on u = 0 (2D functional, wall nodes only):\n";
    const std::vector<Vec3> built = grid.points;
    const Id bad_before = nonpositive_cells(grid);
    const SurfaceOptimizationResult s =
        optimize_wall_surface(grid, *job.body, surface, c.solver.wall_fidelity);
    job.log << untangle::format_untangle_summary(s.solve)
            << fmt::format("  {} wall nodes, {} corner triangles; largest move {:.3g} wall edges\n",
                           s.nodes, s.triangles, s.max_move);
    if (c.domain == Domain::exterior || c.grid.topology != Topology::single_block) {
        try {
            BlockGrid rebuilt =
                build_grid(c, *job.body, &grid.points, &job.route);  // same blocks and node ids
            grid.points = std::move(rebuilt.points);
        } catch (const std::invalid_argument& e) {  // a wall node behind its core node
            job.log << "  no volume can be built from that wall (" << e.what()
                    << "): the grid as constructed is kept\n";
            grid.points = built;
            return;
        }
    } else {
        for (const Block& block : grid.blocks) carry_interior_tfi(block, built, grid.points);
    }
    const Id bad_after = nonpositive_cells(grid);
    if (bad_after > bad_before) {
        job.log << fmt::format(
            "  the volume built from that wall has {} cells with a scaled Jacobian <= 0, "
            "against {} as constructed: the grid as constructed is kept\n",
            bad_after, bad_before);
        grid.points = built;
    }
}

}  // namespace

SurfaceOptimizationResult optimize_wall_surface(BlockGrid& grid, const ImplicitFunction& body,
                                                const untangle::UntangleOptions& options,
                                                double fidelity) {
    SurfaceOptimizationResult result;
    SurfaceProblem s = make_surface_problem(grid, wall_faces(grid), body, fidelity);
    untangle::Problem& p = s.problem;
    result.nodes = Id(s.nodes.size());
    result.triangles = Id(p.triangles.size());
    if (p.triangles.empty()) return result;
    result.solve = untangle::untangle_and_optimize(p, options);
    for (size_t i = 0; i < s.nodes.size(); ++i) {
        Vec3& x = grid.points[s.nodes[i]];
        result.max_move = std::max(result.max_move, (p.points[i] - x).norm() / p.length_scale);
        x = p.points[i];
    }
    return result;
}

void make_surface_grid(Job& job) {
    job.wall_misses.clear();  // a grid made (again): its own stages from here
    note_wall_miss(job, "as placed");
    if (job.route.radial()) {
        const FeatureSnapping snapped = snap_to_features(job.grid(), *job.body);
        if (snapped.crease_nodes + snapped.corner_nodes > 0)
            job.log << fmt::format("  sharp features: {} wall nodes on creases, {} on corners\n",
                                   snapped.crease_nodes, snapped.corner_nodes);
    }
    if (job.settings.solver.surface_iterations > 0) {
        surface_pass(job);
        job.timer.done("surface");
        note_wall_miss(job, "after the surface pass");
    }
}

}  // namespace hexmesh

#include "untangle/untangle.h"

#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "untangle/assembly.h"
#include "untangle/constraints.h"
#include "untangle/minimizer.h"
#include "untangle/regularization.h"

namespace hexmesh::untangle {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double tiny_eps = 1e-10;

// Orders states: fewer inverted elements first, then lower barrier energy.
struct Best {
    std::vector<Vec3> points;
    Id inverted = std::numeric_limits<Id>::max();
    double energy = infinity;
    bool offer(const std::vector<Vec3>& x, Id inv, double barrier_energy) {
        if (inv < inverted || (inv == inverted && barrier_energy < energy)) {
            points = x, inverted = inv, energy = barrier_energy;
            return true;
        }
        return false;
    }
};

void log_line(std::ostream* log, const IterationRecord& r) {
    if (!log) return;
    *log << fmt::format("  {:<9} {:4d}  E {:12.6e}  eps {:9.3e}  min det {:+10.3e}  inverted {:7d}  "
                        "steps {:3d}  cg {:5d}  {:7.2f} s\n",
                        r.barrier ? "optimize" : "untangle", r.iteration, r.energy, r.eps, r.min_det,
                        r.inverted, r.steps, r.linear_iterations, r.seconds);
    log->flush();
}

}  // namespace

UntangleResult untangle_and_optimize(Problem& problem, const UntangleOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto seconds = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    check_constraints(problem);
    project_constrained(problem, problem.points);
    const Assembly assembly(problem);
    std::vector<Vec3>& x = problem.points;

    UntangleResult result;
    ElementStats stats = assembly.stats(x);
    result.inverted_before = stats.inverted;
    result.min_det_before = stats.min_det;
    Best best;
    best.offer(x, stats.inverted, assembly.energy(x, {options.theta, 0}));

    // Untangling: eps continuation (scale free: dets are in target units).
    if (stats.inverted > 0) {
        Minimizer minimizer(problem, assembly, options.untangle_solver);
        double eps = std::sqrt(tiny_eps + 0.04 * stats.min_det * stats.min_det);
        for (int it = 1; it <= options.max_untangle_iterations && stats.inverted > 0; ++it) {
            const EnergyParams p{options.untangle_theta, eps};
            const double e_prev = assembly.energy(x, p);
            // Untangled is the goal of this phase: stop as soon as it is reached.
            const auto untangled = [&](const std::vector<Vec3>& y) { return assembly.stats(y).inverted == 0; };
            const MinimizeOutcome m =
                minimizer.minimize(x, p, options.inner_steps, options.inner_tolerance, untangled);
            stats = assembly.stats(x);
            IterationRecord r{it, false, m.energy, eps, stats.min_det, seconds(), stats.inverted, m.steps,
                              m.linear_iterations};
            result.history.push_back(r);
            log_line(options.log, r);
            best.offer(x, stats.inverted, stats.inverted ? infinity : assembly.energy(x, {options.theta, 0}));
            const double sigma = std::max(1 - m.energy / e_prev, 0.1);
            const double mu = (1 - sigma) * chi(stats.min_det, eps);
            eps = stats.min_det < mu ? 2 * std::sqrt(mu * (mu - stats.min_det)) : tiny_eps;
        }
    }

    // Optimization with the pure barrier, from the best untangled state.
    if (best.inverted == 0) {
        x = best.points;
        Minimizer minimizer(problem, assembly, options.optimize_solver);
        const EnergyParams p{options.theta, 0};
        double e_prev = assembly.energy(x, p);
        for (int it = 1; it <= options.max_optimize_iterations; ++it) {
            const MinimizeOutcome m = minimizer.minimize(x, p, options.inner_steps, options.inner_tolerance);
            stats = assembly.stats(x);
            IterationRecord r{it, true, m.energy, 0.0, stats.min_det, seconds(), stats.inverted, m.steps,
                              m.linear_iterations};
            result.history.push_back(r);
            log_line(options.log, r);
            best.offer(x, stats.inverted, m.energy);
            if (m.steps == 0 || e_prev - m.energy <= options.optimize_tolerance * std::abs(e_prev)) break;
            e_prev = m.energy;
        }
    }

    x = best.points;
    stats = assembly.stats(x);
    result.inverted_after = stats.inverted;
    result.min_det_after = stats.min_det;
    result.energy_after = best.energy;
    result.seconds = seconds();
    return result;
}

std::string format_untangle_summary(const UntangleResult& r) {
    std::string out;
    out += fmt::format("  {:<28}{:>14}{:>14}\n", "", "before", "after");
    out += fmt::format("  {:<28}{:>14}{:>14}\n", "inverted elements", r.inverted_before, r.inverted_after);
    out += fmt::format("  {:<28}{:>14.4g}{:>14.4g}\n", "min det (target units)", r.min_det_before, r.min_det_after);
    int untangle_its = 0, optimize_its = 0;
    for (const IterationRecord& h : r.history) (h.barrier ? optimize_its : untangle_its)++;
    out += fmt::format("  {:<28}{:>28}\n", "outer iterations", fmt::format("{} untangle + {} optimize", untangle_its, optimize_its));
    out += fmt::format("  {:<28}{:>28.2f}\n", "time (s)", r.seconds);
    return out;
}

}  // namespace hexmesh::untangle

#include "untangle/untangle_log.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace hexmesh::untangle {

void log_note(std::ostream* log, const std::string& note) {
    if (!log) return;
    *log << "  " << note << "\n";
    log->flush();
}

void log_line(std::ostream* log, const IterationRecord& r) {
    if (!log) return;
    *log << fmt::format(
        "  {:<9} {:4d}  E {:12.6e}  eps {:9.3e}  min det {:+10.3e}  inverted {:7d}  "
        "steps {:3d}  cg {:5d}  {:7.2f} s\n",
        r.barrier ? "optimize" : "untangle", r.iteration, r.energy, r.eps, r.min_det, r.inverted,
        r.steps, r.linear_iterations, r.seconds);
    log->flush();
}

IterationRecord make_record(int it, bool barrier, const MinimizeOutcome& m, double eps,
                            const ElementStats& stats, double seconds) {
    return {it,
            barrier,
            m.energy,
            eps,
            stats.min_det,
            seconds,
            stats.inverted,
            m.steps,
            m.linear_iterations};
}

void record(UntangleResult& result, std::ostream* log, const IterationRecord& r) {
    result.history.push_back(r);
    log_line(log, r);
}

std::string restart_note(const UntangleOptions& options, int restart_iteration, Id fewest,
                         double eps) {
    return fmt::format(
        "no fewer inverted elements in {} iterations: back to {} "
        "({} inverted, eps {:.3e}), eps now shrinks by the safe rule",
        options.fast_stall,
        restart_iteration ? fmt::format("iteration {}", restart_iteration)
                          : std::string("the start of this pass"),
        fewest, eps);
}

std::string stall_message(bool stuck, double eps, const Progress& progress, double seconds,
                          int stalled) {
    return stuck ? fmt::format("eps fell to {:.1e} with {} inverted elements left", eps,
                               progress.fewest)
                 : fmt::format(
                       "{} for {:.1f} s ({:.0f} % of the untangling work, {} outer iterations of "
                       "this pass)",
                       progress.fell_to == progress.fewest
                           ? fmt::format("no fewer than {} inverted elements", progress.fewest)
                           : fmt::format("not a tenth fewer than {} inverted elements ({} at best)",
                                         progress.fell_to, progress.fewest),
                       seconds - progress.last_fewer_seconds,
                       100 * (progress.work - progress.last_fewer) / std::max(progress.work, 1e-9),
                       stalled);
}

std::string describe_inverted(const Problem& problem, int most) {
    std::string out;
    int n = 0;
    for (Id e = 0; e < problem.num_elements() && n < most; ++e) {
        if (problem.det(problem.points, e) > 0) continue;
        const ElementNodes nodes = problem.element(e);
        Vec3 centre = Vec3::Zero();
        std::array<int, 5> kinds{};
        for (Id v : nodes) centre += problem.points[v] / nodes.size, ++kinds[int(problem.kinds[v])];
        std::string how;
        for (int k = 0; k < 5; ++k)
            if (kinds[k])
                how += fmt::format("{}{} {}", how.empty() ? "" : ", ", kinds[k],
                                   to_string(VertexKind(k)));
        out += fmt::format("{}{} at ({:.4g}, {:.4g}, {:.4g}): {}", n ? "; " : "",
                           problem.is_triangle(e) ? "surface triangle" : "tet", centre.x(),
                           centre.y(), centre.z(), how);
        ++n;
    }
    return out;
}

}  // namespace hexmesh::untangle

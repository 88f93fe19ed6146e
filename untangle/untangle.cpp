// untangle_and_optimize: the eps continuation (local repairs, then global), the last resorts
// for the elements it leaves, and the barrier optimization.
#include "untangle/untangle.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include "untangle/assembly.h"
#include "untangle/constraints.h"
#include "untangle/local_part.h"
#include "untangle/minimizer.h"
#include "untangle/regularization.h"
#include "untangle/untangle_log.h"
#include "untangle/untangle_state.h"

namespace hexmesh::untangle {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double tiny_eps = 1e-10;
constexpr double negligible_eps = 1e-9;

// stall_message, the stop recorded in progress's trace if there is one.
std::string stop_for_stall(bool stuck, double eps, Progress& progress, double seconds,
                           int stalled) {
    if (RoundTrace* t = progress.trace)
        t->stalled_out = true, t->stuck = stuck, t->eps = eps, t->stalled = stalled;
    return stall_message(stuck, eps, progress, seconds, stalled);
}

// The eps of the next outer iteration (docs/architecture.md#the-functional): sigma from the
// energy's decrease (at least the fast or the safe rule's), mu = (1 - sigma) chi(min det, eps).
double next_eps(double energy, double e_prev, bool fast, const UntangleOptions& options,
                double min_det, double eps) {
    const double sigma =
        std::max(1 - energy / e_prev, fast ? options.fast_sigma : options.safe_sigma);
    const double mu = (1 - sigma) * chi(min_det, eps);
    return min_det < mu ? 2 * std::sqrt(mu * (mu - min_det)) : tiny_eps;
}

// options with the stall budget of a pass that another follows, or that follows a stall: 10
// outer iterations without fewer inverted elements.
UntangleOptions with_short_stall(UntangleOptions o) {
    o.stall_iterations = std::min(o.stall_iterations, 10);
    return o;
}

// The first eps of a continuation from a state whose smallest det is min_det, asked to start
// at start_eps or above.
double first_eps(double min_det, double start_eps) {
    return std::max(start_eps, std::sqrt(tiny_eps + 0.04 * min_det * min_det));
}

// The whole problem a continuation answers to (its best state, its progress, when it is done),
// where it solves a part of it (local_part): the whole's assembly and points, and the part's
// place in it (none: the continuation solves the whole).
struct Judge {
    const Assembly& whole;
    const std::vector<Vec3>& points;  // the whole's, where the part's solve starts
    const PartOf* part = nullptr;
    // The whole's stats from those of the problem the continuation solves (`own`).
    ElementStats stats(ElementStats own) const {
        if (!part) return own;
        if (!(part->outside.min_det >= own.min_det)) own.min_det = part->outside.min_det;
        own.inverted += part->outside.inverted;
        return own;
    }
    // Offers the whole's state with the part at x to `best` (with its barrier energy if it is
    // untangled).
    void offer(Best& best, const std::vector<Vec3>& x, Id inverted, double theta) const {
        std::vector<Vec3> scattered;
        if (part) {
            scattered = points;
            for (size_t v = 0; v < x.size(); ++v) scattered[part->global[v]] = x[v];
        }
        const std::vector<Vec3>& y = part ? scattered : x;
        best.offer(y, inverted, inverted ? infinity : whole.energy(y, {theta, 0}));
    }
};

// One outer iteration at p from x, solved: x moves to its end.
OuterIteration solve_outer(Minimizer& minimizer, const Assembly& assembly, const Judge& judge,
                           std::vector<Vec3>& x, const EnergyParams& p,
                           const UntangleOptions& options,
                           const std::function<bool(const ElementStats&)>& done) {
    OuterIteration o;
    o.energy_before = assembly.energy(x, p);
    // Untangled is the goal of this phase: stop as soon as it is reached.
    const auto untangled = [&](const std::vector<Vec3>& y) {
        return done(judge.stats(assembly.stats(y)));
    };
    o.m = minimizer.minimize(x, p, options.inner_steps, options.inner_tolerance, untangled);
    o.local = assembly.stats(x);
    o.stats = judge.stats(o.local);
    return o;
}

// The eps continuation on `problem` (docs/architecture.md#the-functional), from x = problem.points,
// until at most options.unrepairable elements are inverted, the iteration budget is spent or
// progress stalls (then result.stopped says how). Every outer iteration is logged and offered to
// `best` and `progress` (judged on `judge`, the whole problem, since `problem` may be a
// local part of it). eps first shrinks fast; when that stalls, the continuation restarts
// from the best state it reached, at the eps that state was found with, and shrinks eps by
// the safe rule. A continuation asked to start above its state's own eps (start_eps, to give
// the elements room) first adds inverted elements: its progress is then counted from its own
// first iteration, not from the state it left, though the crawl rule (fewer than the best
// state) applies after stall_minimum iterations.
void continuation(Problem& problem, const Judge& judge, const UntangleOptions& options,
                  const std::function<double()>& seconds, Best& best, Progress& progress,
                  UntangleResult& result, double regularize_below = 0, double start_eps = 0) {
    const Assembly assembly(problem);
    std::vector<Vec3>& x = problem.points;
    ElementStats stats = judge.stats(assembly.stats(x));
    Minimizer minimizer(problem, assembly, options.untangle_solver);
    double eps = first_eps(stats.min_det, start_eps);
    const bool from_room = eps > first_eps(stats.min_det, 0);
    bool fast = options.fast_sigma > options.safe_sigma;
    // The best state of this continuation, and its eps.
    Id fewest = from_room ? std::numeric_limits<Id>::max() : stats.inverted;
    std::vector<Vec3> restart = x;
    double restart_eps = eps;
    // slow: iterations of this pass since the count last fell by a tenth (Progress)
    int stalled = 0, restart_iteration = 0, without_fewer = 0, slow = 0;
    const int first = int(result.history.size()) + 1;
    // Regularizing a valid start: the goal is every det above regularize_below instead.
    const std::function<bool(const ElementStats&)> done = [&](const ElementStats& e) {
        return regularize_below > 0 ? e.inverted == 0 && e.min_det >= regularize_below
                                    : e.inverted <= options.unrepairable;
    };
    // The pass's first iteration, kept when it does not lower the count: a restart to the
    // start of the pass would solve it again from the same state and eps, to the same bits.
    FirstIteration once;
    bool back_to_start = false;
    for (int it = first; it < first + options.max_untangle_iterations && !done(stats); ++it) {
        const EnergyParams p{options.untangle_theta, eps, options.equal_weights};
        const bool take = options.reuse_repeats && back_to_start && once.kept();
        if (take)
            log_note(options.log,
                     "the pass's first iteration again (same state, same eps): taken as it was, "
                     "not solved again");
        const OuterIteration o =
            take ? once.take(x) : solve_outer(minimizer, assembly, judge, x, p, options, done);
        if (options.reuse_repeats && it == first && o.stats.inverted >= fewest) once.keep(x, o);
        back_to_start = false;
        const MinimizeOutcome& m = o.m;
        stats = o.stats;
        const IterationRecord r = make_record(it, false, m, eps, stats, seconds());
        record(result, options.log, r);
        judge.offer(best, x, stats.inverted, options.theta);
        // iterations of this pass since the count last fell below the best state's
        without_fewer = stats.inverted < progress.fewest ? 0 : without_fewer + 1;
        slow =
            progress.offer(stats.inverted, 1.0 + double(m.linear_iterations + m.trials), r.seconds)
                ? 0
                : slow + 1;
        if (stats.inverted < fewest || (regularize_below > 0 && stats.inverted == 0)) {
            fewest = stats.inverted, restart = x, restart_eps = eps, stalled = 0,
            restart_iteration = it;
        } else {
            ++stalled;
        }
        if (done(stats)) break;
        if (options.max_work > 0 && progress.work > options.max_work) {
            result.budget_spent = true;
            result.stopped =
                fmt::format("its work budget ({:.0f}) is spent with {} inverted elements left",
                            options.max_work, progress.fewest);
            log_note(options.log, result.stopped);
            return;
        }
        // eps this small (in target units) no longer changes anything but the energy's scale.
        const bool stuck = stalled > 0 && eps < negligible_eps;
        // A pass from above its state's scale has stall_minimum iterations to find fewer
        // inverted elements than the best state; then it is judged as any other.
        const bool judged = stalled >= options.stall_minimum || slow >= options.stall_minimum ||
                            (from_room && it - first + 1 >= options.stall_minimum);
        const bool crawling =
            regularize_below == 0 && judged && progress.ask_crawling(options.stall_share);
        if (fast && !crawling && (stalled >= options.fast_stall || stuck) &&
            stats.inverted > options.unrepairable) {
            if (regularize_below == 0 && options.leave_to_next_pass &&
                options.leave_to_next_pass(best.points)) {
                result.left_to_next_pass = true;
                result.stopped =
                    fmt::format("{} inverted elements left to the next pass", best.inverted);
                log_note(options.log, result.stopped);
                return;
            }
            fast = false, stalled = 0, slow = 0;
            x = restart, eps = restart_eps, back_to_start = restart_iteration == 0;
            stats = judge.stats(assembly.stats(x));
            log_note(options.log, restart_note(options, restart_iteration, fewest, eps));
            continue;
        }
        if (stalled >= options.stall_iterations || stuck || crawling) {
            result.stopped = stop_for_stall(stuck, eps, progress, r.seconds,
                                            std::max(from_room ? without_fewer : stalled, slow));
            return;
        }
        eps = next_eps(m.energy, o.energy_before, fast, options, o.local.min_det, eps);
    }
    if (!done(stats))
        result.stopped =
            fmt::format("the budget of {} outer iterations is spent with {} inverted elements left",
                        options.max_untangle_iterations, progress.fewest);
}

// Repairs the inverted elements of `problem` (x = best.points) in their neighbourhoods of
// options.local_rings element rings, doubled while the neighbourhood is less than half the
// problem and the last round repaired something or grew; the first round starts from
// start_eps (or its state's own scale, when larger), the others from room_eps at least. A
// round that starts as one of `rounds` (the rounds of this untangle_and_optimize call, to
// which it is added) did is not solved again. At most options.local_rounds rounds when that is
// set. Returns whether the last round repaired nothing, and how many rounds ran.
// Whether the untangling call ends with its best state as it is: left to the next pass, or its
// work budget spent (no further round, pass or last resort).
bool handed_over(const UntangleResult& r) {
    return r.left_to_next_pass || r.budget_spent;
}

struct LocalRepair {
    bool stalled = false;
    int rounds = 0;
};
LocalRepair repair_in_neighbourhoods(Problem& problem, const Assembly& assembly,
                                     const std::vector<std::vector<Id>>& elements_of,
                                     const UntangleOptions& options,
                                     const std::function<double()>& seconds, Best& best,
                                     Progress& progress, UntangleResult& result,
                                     std::vector<LocalRound>& rounds, double start_eps = 0) {
    LocalRepair repair;
    if (best.inverted <= options.unrepairable || options.local_rings <= 0) return repair;
    // A part no larger than the last one, after a round that repaired nothing, ends this:
    // more rings add no freedom (few free nodes around cells that cannot be repaired).
    Id previous = 0, inverted_then = std::numeric_limits<Id>::max();
    for (int rings = options.local_rings;
         best.inverted > options.unrepairable && rings < (1 << 20) && !handed_over(result) &&
         (options.local_rounds <= 0 || repair.rounds < options.local_rounds);
         rings *= 2) {
        Problem part;
        PartOf of;
        if (!local_part(problem, elements_of, rings, part, of)) break;
        if (part.num_elements() <= previous && best.inverted >= inverted_then) break;
        ++repair.rounds;
        previous = part.num_elements();
        inverted_then = best.inverted;
        // After the first round, what it left follows eps down (det ~ -eps all the way): a
        // round started at their scale would do the same, so it starts from room_eps.
        const double round_eps =
            rings == options.local_rings ? start_eps : std::max(start_eps, options.room_eps);
        // Only a round from the best state is known by its start (the best state's version);
        // rounds are kept and compared only when repeats are reused.
        const bool known = options.reuse_repeats && problem.points == best.points;
        LocalRound round;
        if (known) {
            round.rings = rings;
            round.eps = first_eps(assembly.stats(problem.points).min_det, round_eps);
            round.best_version = best.version;
            round.kinds = problem.kinds;
        }
        const auto done =
            known ? std::find_if(rounds.begin(), rounds.end(),
                                 [&](const LocalRound& r) { return r.same_start(round); })
                  : rounds.end();
        if (done != rounds.end() && done->decides_as_before(progress, options.stall_share)) {
            log_note(options.log,
                     fmt::format("neighbourhoods of {} rings from the same state and eps {:.3e} "
                                 "as before: {} iterations taken as they were, not solved again",
                                 rings, round.eps, done->iterations));
            progress.offer(best.inverted, done->work, seconds());
            const RoundTrace& t = done->trace;
            result.stopped = t.stalled_out
                                 ? stall_message(t.stuck, t.eps, progress, seconds(), t.stalled)
                                 : done->stopped;
            result.left_to_next_pass = done->left_to_next_pass;
            repair.stalled = true;
            continue;
        }
        if (rings != options.local_rings && round_eps > start_eps)
            log_note(options.log,
                     fmt::format("{} inverted elements left: neighbourhoods of {} rings, from eps "
                                 "{:.3g} or above",
                                 best.inverted, rings, round_eps));
        UntangleOptions local = with_short_stall(options);  // the global pass follows
        local.max_untangle_iterations = std::min(options.max_untangle_iterations, 50);
        const size_t records = result.history.size();
        round.start_work = progress.work;
        progress.trace = known ? &round.trace : nullptr;
        continuation(part, Judge{assembly, problem.points, &of}, local, seconds, best, progress,
                     result, 0, round_eps);
        progress.trace = nullptr;
        repair.stalled = best.inverted >= inverted_then;
        problem.points = best.points;
        if (!known) continue;
        round.iterations = int(result.history.size() - records);
        round.work = progress.work - round.start_work;
        round.stopped = result.stopped;
        round.left_to_next_pass = result.left_to_next_pass;
        rounds.push_back(std::move(round));
    }
    return repair;
}

// What the passes of one untangle_and_optimize call share: the problem (x = its points), its
// assembly, per vertex the elements it belongs to (for the local repair), and the best state,
// progress and result every pass updates.
struct Passes {
    Problem& problem;
    const Assembly& assembly;
    const std::vector<std::vector<Id>>& elements_of;
    const UntangleOptions& options;
    const std::function<double()>& seconds;
    Best& best;
    Progress& progress;
    UntangleResult& result;
    std::vector<LocalRound>& rounds;

    // The continuations of the whole problem answer to it.
    Judge whole() const { return Judge{assembly, problem.points}; }
    // repair_in_neighbourhoods from start_eps.
    LocalRepair repair_locally(double start_eps) const {
        return repair_in_neighbourhoods(problem, assembly, elements_of, options, seconds, best,
                                        progress, result, rounds, start_eps);
    }
};

void release_creases(const Passes& s);

// A vertex held on a crease line or at a corner (what release_creases lets slide).
bool on_crease(VertexKind kind) {
    return kind == VertexKind::feature_edge || kind == VertexKind::corner;
}

// Whether every element still inverted has a crease or corner vertex (and releasing them is
// allowed): what the local repair could not free is then held by the crease lines.
bool held_by_creases(const Passes& s) {
    const Problem& problem = s.problem;
    if (s.best.inverted <= s.options.unrepairable || !s.options.release_creases) return false;
    for (Id e = 0; e < problem.num_elements(); ++e) {
        if (problem.det(problem.points, e) > 0) continue;
        const ElementNodes nodes = problem.element(e);
        if (std::none_of(nodes.begin(), nodes.end(),
                         [&](Id v) { return on_crease(problem.kinds[v]); }))
            return false;
    }
    return true;
}

// Untangling. Few inverted elements are first repaired locally, in growing neighbourhoods;
// what is left (or a widespread tangle) is untangled globally. x = the best state after.
// When the widest neighbourhood repaired nothing and every element left has a crease or
// corner vertex, those vertices are released first (release_creases): the global pass moves
// the whole mesh and cannot unfold a quad folded across a crease line either (NACA0012
// outside: 3.5 s of global steps on 3 such elements, then the release freed them at once).
// With options.local_rounds set, elements the local repair leaves inverted after its rounds
// are left to the next pass (another way of making the grid): no global pass, no last resort.
void untangle_locally_then_globally(const Passes& s) {
    const LocalRepair local = s.repair_locally(0);
    if (s.options.local_rounds > 0 && local.rounds > 0 &&
        s.best.inverted > s.options.unrepairable && !s.result.left_to_next_pass) {
        s.result.left_to_next_pass = true;
        s.result.stopped = fmt::format(
            "{} inverted elements left after {} rounds of local repair: left to the "
            "next pass",
            s.best.inverted, local.rounds);
        log_note(s.options.log, s.result.stopped);
    }
    if (local.stalled && !s.result.left_to_next_pass && held_by_creases(s)) release_creases(s);
    if (s.best.inverted > s.options.unrepairable && !handed_over(s.result)) {
        // When the largest neighbourhood the local repair tried repaired nothing, the global
        // pass gets the local stall budget too: what is left is then almost always blocked
        // (an element held by fixed vertices, or by such a neighbour).
        const UntangleOptions global = local.stalled ? with_short_stall(s.options) : s.options;
        // From its state's own scale: from room_eps, as the later local rounds, the whole mesh
        // would first add many inverted elements (the hand outside: 23 -> 149), at the cost of
        // the largest solves.
        continuation(s.problem, s.whole(), global, s.seconds, s.best, s.progress, s.result);
    }
    s.problem.points = s.best.points;
}

// Validity before fidelity: when the untangling leaves inverted elements with the wall held to
// the body (Problem::held_quads), the quads are let go and it starts again from its best state
// (a fold of the wall that only a node sliding off a limb's tip undoes).
void let_the_wall_go(const Passes& s) {
    if (s.best.inverted <= s.options.unrepairable || s.problem.held_quads.empty() ||
        s.result.budget_spent)
        return;
    log_note(s.options.log, fmt::format("{} inverted elements left with the wall held to the body: "
                                        "its quads let go",
                                        s.best.inverted));
    s.problem.held_quads.clear();
    s.rounds.clear();  // solved with the quads: not the same functional
    s.result.wall_let_go = true;
    s.result.left_to_next_pass = false;
    s.result.stopped.clear();
    s.progress.start_again(s.seconds());  // new freedom: the stall clock starts again
    untangle_locally_then_globally(s);
}

// The few elements the continuation leaves often have det ~ -eps all the way down (each
// step of eps is matched by their det): their neighbourhoods start again from room_eps,
// where the functional lets them move; the whole mesh does when their neighbourhoods are more
// than half of it (a small mesh) and room_eps is above its scale.
void restart_from_room_eps(const Passes& s) {
    const UntangleOptions& options = s.options;
    if (s.best.inverted <= options.unrepairable || options.room_eps <= 0 ||
        options.local_rings <= 0 || handed_over(s.result))
        return;
    // From room_eps, or from 0.2 |min det| as every continuation when that is larger.
    const double min_det = s.assembly.stats(s.best.points).min_det;
    const double eps = first_eps(min_det, options.room_eps);
    Problem part;
    PartOf of;
    const bool fits = local_part(s.problem, s.elements_of, options.local_rings, part, of);
    const bool whole = !fits && part.num_elements() >= s.problem.num_elements() / 2;
    // No free vertex near them: nothing can move. The whole mesh only from above its best
    // state's own scale: at that scale it would start as the global pass did.
    if (!fits && !(whole && eps > first_eps(min_det, 0))) return;
    s.progress.start_again(s.seconds());  // a new start: the stall clock starts again
    if (whole) {
        log_note(options.log,
                 fmt::format("{} inverted elements left: their neighbourhoods are more than half "
                             "the mesh: the whole mesh starts again instead, from eps {:.3g}",
                             s.best.inverted, eps));
        continuation(s.problem, s.whole(), with_short_stall(options), s.seconds, s.best, s.progress,
                     s.result, 0, options.room_eps);
    } else {
        log_note(options.log,
                 fmt::format("{} inverted elements left: their neighbourhoods start again from eps "
                             "{:.3g}",
                             s.best.inverted, eps));
        s.repair_locally(options.room_eps);
    }
    s.problem.points = s.best.points;
}

// Last resort: the crease and corner vertices of the elements still inverted slide on the
// surface instead (a wall quad folded across a crease cannot unfold while its vertex is
// held on the crease line), and the local repair runs again. Their kinds come back after.
void release_creases(const Passes& s) {
    Problem& problem = s.problem;
    const UntangleOptions& options = s.options;
    if (s.best.inverted > options.unrepairable && options.release_creases &&
        options.local_rings > 0 && problem.project_to_surface && problem.surface_normal &&
        !handed_over(s.result)) {
        const std::vector<VertexKind> kinds = problem.kinds;
        // Counted per call: it runs once more, as the last resort, after an earlier release
        // before the global pass (untangle_locally_then_globally) left elements inverted.
        Id released = 0;
        for (Id e = 0; e < problem.num_elements(); ++e)
            if (!(problem.det(problem.points, e) > 0))
                for (Id v : problem.element(e))
                    if (on_crease(problem.kinds[v]))
                        problem.kinds[v] = VertexKind::slip, ++released;
        s.result.released += released;
        if (released > 0) {
            s.progress.start_again(s.seconds());  // new freedom: the stall clock starts again
            log_note(
                options.log,
                fmt::format("{} crease and corner vertices of the inverted elements now slide on "
                            "the surface",
                            released));
            s.repair_locally(options.room_eps);
            problem.points = s.best.points;
        }
        problem.kinds = kinds;
    }
}

// Optimization with the pure barrier, from the best untangled state (if there is one).
void optimize_with_barrier(const Passes& s) {
    if (s.best.inverted != 0) return;
    const UntangleOptions& options = s.options;
    std::vector<Vec3>& x = s.problem.points;
    x = s.best.points;
    Minimizer minimizer(s.problem, s.assembly, options.optimize_solver);
    const EnergyParams p{options.theta, 0};
    double e_prev = s.assembly.energy(x, p);
    for (int it = 1; it <= options.max_optimize_iterations; ++it) {
        const MinimizeOutcome m =
            minimizer.minimize(x, p, options.inner_steps, options.optimize_tolerance);
        const ElementStats stats = s.assembly.stats(x);
        record(s.result, options.log, make_record(it, true, m, 0.0, stats, s.seconds()));
        s.best.offer(x, stats.inverted, m.energy);
        // eps stays 0 here: an inner solve that converged before its step budget would
        // only be confirmed by another outer iteration.
        if (m.steps < options.inner_steps ||
            e_prev - m.energy <= options.optimize_tolerance * std::abs(e_prev))
            break;
        e_prev = m.energy;
    }
}

// x = the best state; the result's final statistics, and why untangling stopped if it left
// more inverted elements than options.unrepairable.
void finish(const Passes& s) {
    UntangleResult& result = s.result;
    std::vector<Vec3>& x = s.problem.points;
    x = s.best.points;
    const ElementStats stats = s.assembly.stats(x);
    if (stats.inverted <= s.options.unrepairable)
        result.stopped.clear();
    else if (result.blocked > s.options.unrepairable)
        result.stopped = fmt::format(
            "{} inverted elements have every vertex held (fixed): no solve can repair them",
            result.blocked);
    if (!result.stopped.empty()) result.stopped += "; inverted: " + describe_inverted(s.problem, 3);
    result.inverted_after = stats.inverted;
    result.min_det_after = stats.min_det;
    result.energy_after = s.best.energy;
    result.seconds = s.seconds();
    result.work = s.progress.work;
}

}  // namespace

UntangleResult untangle_and_optimize(Problem& problem, const UntangleOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const std::function<double()> seconds = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    check_constraints(problem);
    project_constrained(problem, problem.points);
    const Assembly assembly(problem);
    std::vector<Vec3>& x = problem.points;

    UntangleResult result;
    const ElementStats stats = assembly.stats(x);
    result.inverted_before = stats.inverted;
    result.min_det_before = stats.min_det;
    Best best;
    best.offer(x, stats.inverted, assembly.energy(x, {options.theta, 0}));
    Progress progress;
    progress.offer(stats.inverted, 0, 0);
    result.blocked = Id(problem.blocked_elements().size());

    std::vector<std::vector<Id>> elements_of;
    if (options.local_rings > 0) {
        elements_of.resize(x.size());
        for (Id e = 0; e < problem.num_elements(); ++e)
            for (Id v : problem.element(e)) elements_of[v].push_back(e);
    }
    std::vector<LocalRound> rounds;
    const Passes passes{problem, assembly, elements_of, options, seconds,
                        best,    progress, result,      rounds};
    untangle_locally_then_globally(passes);
    let_the_wall_go(passes);
    restart_from_room_eps(passes);
    release_creases(passes);
    if (best.inverted == 0 && options.regularize_below > 0 &&
        assembly.stats(x).min_det < options.regularize_below) {
        continuation(problem, passes.whole(), options, seconds, best, progress, result,
                     options.regularize_below);
        x = best.points;  // the valid state of lowest barrier energy
    }
    optimize_with_barrier(passes);
    finish(passes);
    return result;
}

std::string format_untangle_summary(const UntangleResult& r) {
    std::string out;
    out += fmt::format("  {:<28}{:>14}{:>14}\n", "", "before", "after");
    out += fmt::format("  {:<28}{:>14}{:>14}\n", "inverted elements", r.inverted_before,
                       r.inverted_after);
    out += fmt::format("  {:<28}{:>14.4g}{:>14.4g}\n", "min det (target units)", r.min_det_before,
                       r.min_det_after);
    int untangle_its = 0, optimize_its = 0;
    for (const IterationRecord& h : r.history) (h.barrier ? optimize_its : untangle_its)++;
    out += fmt::format("  {:<28}{:>28}\n", "outer iterations",
                       fmt::format("{} untangle + {} optimize", untangle_its, optimize_its));
    out += fmt::format("  {:<28}{:>28.2f}\n", "time (s)", r.seconds);
    if (r.released > 0)
        out += fmt::format("  {:<28}{:>28}\n", "crease vertices released",
                           fmt::format("{} (slide on the surface)", r.released));
    if (!r.stopped.empty()) out += fmt::format("  untangling stopped: {}\n", r.stopped);
    return out;
}

}  // namespace hexmesh::untangle

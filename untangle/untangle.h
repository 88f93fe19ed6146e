// The continuation driver: untangle with a shrinking eps, then optimize with the pure barrier.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "untangle/problem.h"
#include "untangle/solver_options.h"
#include "untangle/tet_energy.h"

namespace hexmesh::untangle {

// Solver options whose linear solves stop at a relative residual of 0.1.
inline SolverOptions loose_solve() {
    SolverOptions o;
    o.cg_tolerance = 0.1;
    return o;
}

struct UntangleOptions {
    SolverOptions untangle_solver;  // while some det <= 0 (global method recommended)
    // Once all det > 0, eps = 0 (barrier). Its linear solves stop at a relative residual of
    // 0.1: the optimized grid is the same to the digits reported (min and mean scaled
    // Jacobian) as with 0.01, for about half the CG iterations.
    SolverOptions optimize_solver = loose_solve();
    double theta = default_theta;  // volume weight while optimizing (untangle/tet_energy.h)
    double untangle_theta = 0.1;   // volume weight while untangling: shape first is more robust
    // While untangling (eps > 0), every tet weighs the same (EnergyParams::equal_weights)
    // instead of its target's volume. The barrier optimization always weighs by volume (the
    // functional as published). `run` sets it for exterior grids
    // (docs/architecture.md#the-functional).
    bool equal_weights = false;
    int max_untangle_iterations = 200;  // outer iterations (eps updates)
    // When > 0: untangling ends, with the best state it reached, once its work (Progress:
    // outer iterations, their conjugate-gradient iterations and line searches' evaluations;
    // the same on every machine) exceeds this. For a grid made again only to be compared with
    // one already made: it is given a multiple of that one's work.
    double max_work = 0;
    int stall_iterations = 40;  // stop untangling after this many without progress
    // Untangling also stops when the inverted count has not fallen by a tenth (Progress) for
    // longer than this share of the work done so far (outer iterations, their
    // conjugate-gradient iterations and their line searches' energy evaluations: a measure of
    // time that does not depend on the machine or its load, so that a case gives the same grid
    // on every run), after at least stall_minimum outer iterations of the pass without fewer
    // or without a fall (counted again from the switch to the safe rule): a continuation that
    // crawls or cycles ends, with the reason in UntangleResult::stopped (one that crawls while
    // eps still shrinks fast ends too, without the safe rule: going back to its best state,
    // at its tiny eps, it would crawl on more slowly). The safe rule often
    // raises the count for a few iterations before it falls (an exterior grid of a cross:
    // 626 -> 728 -> 623 over 6 iterations, then valid): it gets those.
    double stall_share = 0.15;
    int stall_minimum = 8;
    // eps continuation speed: eps shrinks as if each inner solve had lowered the energy by at
    // least this share (the sigma floor of docs/architecture.md#the-functional). Untangling starts
    // with fast_sigma (about 5x smaller eps per outer iteration) and, after fast_stall iterations
    // without fewer inverted elements, goes back to its best state and on with safe_sigma, the
    // floor of the published rule (about 10 % per iteration).
    double fast_sigma = 0.8;
    double safe_sigma = 0.1;
    int fast_stall = 2;
    // Inverted elements are first repaired in their neighbourhood of this many element
    // rings (doubled until it works or covers half the mesh); 0 untangles globally only.
    int local_rings = 2;
    // When > 0: the local repair tries at most this many neighbourhood sizes (each round
    // doubles the rings), and the elements it leaves inverted in its first call are left to
    // the next pass (UntangleResult::left_to_next_pass), without the global pass or the last
    // resorts below: for a grid made again another way when it stays tangled. Those later
    // stages solve ever larger parts (the hand outside: 39 s of 56 s on 11 inverted elements,
    // which none of them freed). 0: every size that fits, then the global pass.
    int local_rounds = 0;
    // eps (target units) the local repair starts again from when elements stay inverted after
    // the local and global passes (0: no second start), and that every round of the local
    // repair after its first starts from.
    double room_eps = 0.1;
    // When elements stay inverted, the crease and corner vertices among theirs slide on the
    // surface instead and the local repair runs again (validity before the crease's sharpness).
    bool release_creases = true;
    // Outer iterations and local rounds that start exactly as one already done (the start of
    // a pass after a restart to it; a round of the same rings from the same best state and
    // eps, after a last resort that did not change either) end exactly as it did: they are
    // taken from it instead of being solved again. false solves them again (same result).
    bool reuse_repeats = true;
    int max_optimize_iterations = 20;
    int inner_steps = 30;  // descent steps per outer iteration
    // Relative energy decrease that ends an inner untangling solve. Each eps is one stage of
    // the continuation, not worth solving to the end: with 1e-3 instead of 1e-6 every shared
    // mesh untangles in the same outer iterations, 2-3x faster, to about the same min scaled
    // Jacobian (bench/RESULTS.md, "Untangler").
    double inner_tolerance = 1e-3;
    // Relative energy change that ends optimization: a barrier step (and so an outer
    // iteration) that lowers F by less ends it.
    double optimize_tolerance = 1e-5;
    std::ostream* log = nullptr;  // one progress line per outer iteration
    // Elements known to stay inverted whatever is done (all their vertices fixed): untangling
    // stops once only that many remain.
    Id unrepairable = 0;
    // A start with no inverted element but some det S below this (target units) is first
    // evened out by the eps continuation, as if it were tangled, until every det S is above it
    // or the untangling budget is spent: a one-to-one map whose dets span many orders of
    // magnitude (Tutte's embedding of a body with legs: 1e-20) leaves the barrier's Newton
    // steps no room, while with eps > 0 the tiny dets weigh like eps. 0: never.
    double regularize_below = 0;
    // Whether the inverted elements of a state (its points) may be left to a later pass that
    // repairs them better (`run`: the boundary layer laid again along the wall normals frees
    // those at the wall and its layers). It is asked of the best state reached whenever a
    // continuation's fast phase stalls (the first stall of the local repair, of the global
    // pass, ...); when it says yes, untangling ends there (UntangleResult::left_to_next_pass)
    // instead of going on by the safe rule or trying its last resorts. Not while evening out
    // a valid start (regularize_below). Empty: never.
    std::function<bool(const std::vector<Vec3>&)> leave_to_next_pass;
};

// One line of the progress log.
struct IterationRecord {
    int iteration = 0;
    bool barrier = false;  // false: untangling (eps > 0); true: optimizing (eps = 0)
    double energy = 0, eps = 0, min_det = 0, seconds = 0;
    Id inverted = 0;
    int steps = 0, linear_iterations = 0;
};

struct UntangleResult {
    Id inverted_before = 0, inverted_after = 0;  // elements with det S <= 0
    Id blocked = 0;   // inverted elements whose vertices are all held: no solve repairs them
    Id released = 0;  // crease and corner vertices let slide on the surface (release_creases)
    // The untangling stalled with the wall held to the body (Problem::held_quads): the quads
    // were let go and the untangling went on without them (validity before fidelity).
    bool wall_let_go = false;
    // options.leave_to_next_pass took the inverted elements left, or options.local_rounds left them
    bool left_to_next_pass = false;
    // Why untangling ended with inverted elements beyond options.unrepairable, for the user
    // ("no fewer than 3 inverted elements for 12.1 s, 31 % of the untangling time"); empty
    // when it reached its goal.
    std::string stopped;
    double min_det_before = 0, min_det_after = 0;  // in target units (1 = perfect)
    double energy_after = 0;                       // barrier energy, +inf if still tangled
    double seconds = 0;
    // The untangling's work (UntangleOptions::max_work), and whether it reached that budget.
    double work = 0;
    bool budget_spent = false;
    std::vector<IterationRecord> history;
};

// Minimizes the functional (docs/architecture.md#the-functional) over problem.points (updated in
// place): eps continuation from the foldover-free rule until every element has det S > 0, then
// barrier optimization. Never returns worse than its input: the best state seen (fewest inverted
// elements, then lowest energy) is the one kept.
UntangleResult untangle_and_optimize(Problem& problem, const UntangleOptions& options);

// The summary table printed at the end of a run.
std::string format_untangle_summary(const UntangleResult& result);

}  // namespace hexmesh::untangle

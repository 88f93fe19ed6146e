// What one untangle_and_optimize call keeps across its passes: the best state seen, when the
// inverted count last fell, and the outcomes of its own solves. Its restarts can go back to a
// state and eps it has already solved from, and its solves are deterministic (the same input
// gives the same bits): such a solve is taken as it was instead of being solved again.
#pragma once

#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "hexmesh/core/vertex_kind.h"
#include "untangle/assembly.h"
#include "untangle/minimizer.h"

namespace hexmesh::untangle {

// Orders states: fewer inverted elements first, then lower barrier energy.
struct Best {
    std::vector<Vec3> points;
    Id inverted = std::numeric_limits<Id>::max();
    double energy = std::numeric_limits<double>::infinity();
    int version = 0;  // how many times a state was taken: equal versions, equal points
    bool offer(const std::vector<Vec3>& x, Id inv, double barrier_energy) {
        if (inv < inverted || (inv == inverted && barrier_energy < energy)) {
            points = x, inverted = inv, energy = barrier_energy, ++version;
            return true;
        }
        return false;
    }
};

// What a continuation read from Progress and how it ended, recorded for a local round: every
// answer of the crawl rule (the work when asked, the answer), and whether the stall rule ended
// it (stuck: eps negligible; at eps, after `stalled` iterations without fewer).
struct RoundTrace {
    std::vector<std::pair<double, bool>> crawl;
    bool stalled_out = false, stuck = false;
    double eps = 0;
    int stalled = 0;
};

// When the inverted count last fell by a tenth, over all passes of one untangle_and_optimize
// call, in work done (each outer iteration 1 plus its conjugate-gradient iterations and its
// line searches' energy evaluations, each a pass over the problem's elements: deterministic,
// unlike the clock, and whole numbers, so sums are exact) and in seconds (for the message).
// At a tiny eps a Newton step is often taken only after many halvings, or none is found after
// max_halvings: an outer iteration of a few conjugate-gradient iterations then costs some 40
// evaluations. A fall counts when the count drops to `fell_to` less a tenth of it (at least 1:
// under 20 inverted elements, any fall), so that a continuation that crawls (121 -> 100
// inverted elements over 38 outer iterations and 60 s, one element every few iterations) is
// judged as one that makes no progress.
struct Progress {
    Id fewest = std::numeric_limits<Id>::max();
    Id fell_to = std::numeric_limits<Id>::max();  // the count at the last fall
    double work = 0, last_fewer = 0, last_fewer_seconds = 0;
    RoundTrace* trace = nullptr;  // when set, the crawl rule's answers are recorded there
    // Returns whether the count fell (by a tenth).
    bool offer(Id inverted, double iteration_work, double seconds) {
        work += iteration_work;
        fewest = std::min(fewest, inverted);
        if (inverted > fell_to - std::max<Id>(1, fell_to / 10)) return false;
        fell_to = inverted, last_fewer = work, last_fewer_seconds = seconds;
        return true;
    }
    void start_again(double seconds) {
        fell_to = fewest, last_fewer = work, last_fewer_seconds = seconds;
    }
    // Whether the count has not fallen for longer than `share` of the work so far.
    bool crawling(double share) const { return crawling_at(work, share); }
    bool crawling_at(double w, double share) const { return w - last_fewer > share * w; }
    // crawling(share), recorded in the trace if there is one.
    bool ask_crawling(double share) {
        const bool c = crawling(share);
        if (trace) trace->crawl.emplace_back(work, c);
        return c;
    }
};

// One outer iteration of the eps continuation: the energy before its solve, the solve's
// outcome, and the element stats after it of the whole problem and of the part solved.
struct OuterIteration {
    double energy_before = 0;
    MinimizeOutcome m;
    ElementStats stats, local;
};

// The first outer iteration of a continuation pass, kept: a restart to the start of the pass
// (its state, its eps) would solve it again to the same bits.
class FirstIteration {
  public:
    bool kept() const { return kept_; }
    // x: the state the iteration ended in.
    void keep(const std::vector<Vec3>& x, const OuterIteration& outcome) {
        after_ = x, outcome_ = outcome, kept_ = true;
    }
    // x becomes the state the first iteration ended in; returns its outcome.
    const OuterIteration& take(std::vector<Vec3>& x) const {
        x = after_;
        return outcome_;
    }

  private:
    std::vector<Vec3> after_;
    OuterIteration outcome_;
    bool kept_ = false;
};

// A round of the local repair: its start (neighbourhood rings, first eps, the best state's
// version, the vertices' kinds) and what it did. A round with the same start solves the same
// part from the same state to the same bits, and leaves the best state as it found it (a round
// that improves it changes its version), so it is taken as it was.
struct LocalRound {
    int rings = 0;
    double eps = 0;
    int best_version = 0;
    std::vector<VertexKind> kinds;
    int iterations = 0;
    double start_work = 0;  // Progress work when it started
    double work = 0;  // its Progress work, offered again so that later passes decide as before
    RoundTrace trace;
    std::string stopped;
    bool left_to_next_pass = false;
    bool same_start(const LocalRound& o) const {
        return rings == o.rings && eps == o.eps && best_version == o.best_version &&
               kinds == o.kinds;
    }
    // Whether the round, started now, would get the same answers from the crawl rule: it
    // does not lower the count, so Progress's last fall stays where it is now.
    bool decides_as_before(const Progress& now, double share) const {
        for (const auto& [asked, answer] : trace.crawl)
            if (now.crawling_at(now.work + (asked - start_work), share) != answer) return false;
        return true;
    }
};

}  // namespace hexmesh::untangle

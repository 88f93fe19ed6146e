// What the untangler prints and says: one progress line per outer iteration, the notes of its
// restarts and last resorts, why it stopped, and where the inverted elements it left are.
#pragma once

#include <ostream>
#include <string>

#include "untangle/assembly.h"
#include "untangle/minimizer.h"
#include "untangle/untangle.h"
#include "untangle/untangle_state.h"

namespace hexmesh::untangle {

// Writes "  note" and a newline to `log` (nothing when it is null).
void log_note(std::ostream* log, const std::string& note);

// The progress line of outer iteration r (nothing when `log` is null).
void log_line(std::ostream* log, const IterationRecord& r);

// The record of outer iteration `it` that ended in m with `stats` (of the whole problem).
IterationRecord make_record(int it, bool barrier, const MinimizeOutcome& m, double eps,
                            const ElementStats& stats, double seconds);

// Appends r to the history and logs it.
void record(UntangleResult& result, std::ostream* log, const IterationRecord& r);

// The note logged when eps stops shrinking fast and the continuation goes back to its best
// state (found at restart_iteration, 0 for the start of the pass; fewest inverted at eps).
std::string restart_note(const UntangleOptions& options, int restart_iteration, Id fewest,
                         double eps);

// Why a continuation stalled: eps became negligible (stuck), or the inverted count has not
// fallen (by a tenth: Progress) for too long (`stalled` outer iterations, up to `seconds`).
std::string stall_message(bool stuck, double eps, const Progress& progress, double seconds,
                          int stalled);

// Where the first `most` inverted elements of `problem` are and how their vertices may move
// ("at (0.34, -0.09, -0.16): 1 interior, 2 slip, 1 feature_edge"), one per "; ".
std::string describe_inverted(const Problem& problem, int most);

}  // namespace hexmesh::untangle

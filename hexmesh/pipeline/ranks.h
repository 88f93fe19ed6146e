// The processes of a job started by an MPI launcher (`mpirun -np N hexmesh ...`), or this
// process alone: who we are, and the few collective steps the jobs need.
#pragma once

#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh::ranks {

// Starts MPI when the launcher's environment says this process is one of several (Open MPI's
// OMPI_COMM_WORLD_SIZE, PMI's PMI_SIZE), and ends it on destruction; otherwise (a plain
// command line) nothing is started and this process is rank 0 of 1. One per program, in
// main(). Throws std::runtime_error when started by a launcher but built without MPI.
class Session {
  public:
    Session(int& argc, char**& argv);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;
};

// An error every rank throws alike (after a collective step that told them all): rank 0
// reports it, the others need not repeat it.
struct EveryRankError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

int rank();  // 0 .. size() - 1
int size();  // 1 without a launcher

// At rank 0, every rank's `bytes` in rank order; at the others, nothing (collective).
std::vector<std::string> gather(const std::string& bytes);

// Rank 0's `bytes`, on every rank (collective).
std::string broadcast(const std::string& bytes);

// The sum of every rank's n, on every rank (collective).
Id sum(Id n);

// The largest of every rank's values, entry by entry, on every rank (collective).
std::vector<double> max(std::vector<double> values);

// Rethrows `error` as a std::runtime_error of the same message (std::bad_alloc as itself): an
// error of this rank alone, which it reports itself.
[[noreturn]] void rethrow_as_own(std::exception_ptr error);

// Runs f() on every rank (collective); when it throws on any rank, it throws on every one:
// its own error where it failed (as the rank's own, rethrow_as_own, unless every rank failed,
// when rank 0 speaks for all), EveryRankError elsewhere, so no rank waits for one gone. f()
// must not itself call a collective step after something that can throw on some ranks only.
template <class F>
void together(F&& f) {
    std::exception_ptr error;
    try {
        f();
    } catch (...) {
        error = std::current_exception();
    }
    const Id failed = sum(error ? 1 : 0);
    if (failed == 0) return;
    if (!error) throw EveryRankError("another process failed (its error above); nothing written");
    if (failed < size()) rethrow_as_own(error);
    std::rethrow_exception(error);
}

}  // namespace hexmesh::ranks

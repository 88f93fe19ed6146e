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

// Whether every rank passes `ok` (collective: every rank calls it at the same point).
bool all(bool ok);

// At rank 0, every rank's `bytes` in rank order; at the others, nothing (collective).
std::vector<std::string> gather(const std::string& bytes);

// Rank 0's `bytes`, on every rank (collective).
std::string broadcast(const std::string& bytes);

// The sum of every rank's n, on every rank (collective).
Id sum(Id n);

// Runs f() on every rank (collective); when it throws on any rank, it throws on every one:
// its own error where it failed, EveryRankError elsewhere (so no rank waits for one gone).
template <class F>
void together(F&& f) {
    std::exception_ptr error;
    try {
        f();
    } catch (...) {
        error = std::current_exception();
    }
    if (all(!error)) return;
    if (error) std::rethrow_exception(error);
    throw EveryRankError("another process failed (its error above); nothing written");
}

}  // namespace hexmesh::ranks

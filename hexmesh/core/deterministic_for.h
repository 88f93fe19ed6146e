// A parallel loop whose failure does not depend on the threads: the error a user reads names
// the same place on every machine.
#pragma once

#include <tbb/parallel_for.h>

#include <exception>
#include <mutex>

#include "hexmesh/core/types.h"

namespace hexmesh {

// body(i) for every i in [0, n), in parallel. When some throw, every index still runs and the
// exception of the smallest index that threw is rethrown after the loop.
template <class Body>
void deterministic_for(Id n, Body&& body) {
    std::mutex mutex;
    Id first = n;
    std::exception_ptr error;
    tbb::parallel_for(Id(0), n, [&](Id i) {
        try {
            body(i);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(mutex);
            if (i < first) first = i, error = std::current_exception();
        }
    });
    if (error) std::rethrow_exception(error);
}

}  // namespace hexmesh

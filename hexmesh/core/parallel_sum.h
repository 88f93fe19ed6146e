// A parallel sum that gives the same bits whatever the threads: the one reduction of the
// solvers and the fields (conjugate gradients, energies, the exterior potential).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cstddef>

namespace hexmesh {

// Sum of term(i) for i in [0, n), in parallel: the range is split by n and `grain` only, never
// by the threads, and the partial sums are added in the same tree, so a run gives the same
// result on any machine load. term may write element i of vectors as it goes.
template <class Term>
double deterministic_sum(std::size_t n, std::size_t grain, Term&& term) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, n, grain), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double s) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) s += term(i);
            return s;
        },
        [](double a, double b) { return a + b; }, tbb::simple_partitioner());
}

}  // namespace hexmesh

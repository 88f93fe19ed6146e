#include "hexmesh/core/memory_limit.h"

#include <sys/resource.h>
#include <unistd.h>

#include <atomic>

namespace hexmesh {
namespace {

std::atomic<double> limit{0};

}  // namespace

double memory_limit() {
    if (const double set = limit.load(); set > 0) return set;
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? 0.5 * double(pages) * double(page) : 8e9;
}

void set_memory_limit(double bytes) {
    limit.store(bytes > 0 ? bytes : 0);
}

double peak_memory() {
    rusage usage{};
    return getrusage(RUSAGE_SELF, &usage) == 0 ? 1024.0 * double(usage.ru_maxrss) : 0;
}

}  // namespace hexmesh

// A histogram of equal bins over [lo, hi), with the values below and above it counted apart.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

struct Histogram {
    double lo = 0, hi = 1;
    std::vector<Id> counts;  // bin b holds [lo + b w, lo + (b + 1) w), w = (hi - lo) / bins
    Id below = 0;            // values under lo
    Id above = 0;            // values at hi or over it, and values that are not numbers

    Histogram() = default;
    Histogram(double lo_, double hi_, int bins) : lo(lo_), hi(hi_), counts(bins, 0) {}

    void add(double v) {
        if (!(v < hi) || counts.empty())
            ++above;  // NaN too
        else if (v < lo)
            ++below;
        else {
            const auto bin = static_cast<std::size_t>((v - lo) / (hi - lo) * double(counts.size()));
            ++counts[std::min(bin, counts.size() - 1)];
        }
    }
    // Adds the counts of a histogram of the same bins (an empty one adopts the other's bins).
    void join(const Histogram& o) {
        if (counts.empty()) {
            *this = o;
            return;
        }
        for (std::size_t b = 0; b < counts.size() && b < o.counts.size(); ++b)
            counts[b] += o.counts[b];
        below += o.below;
        above += o.above;
    }
    Histogram empty_copy() const { return Histogram(lo, hi, int(counts.size())); }
    Id total() const {
        Id n = below + above;
        for (Id c : counts) n += c;
        return n;
    }
    double bin_width() const { return (hi - lo) / double(counts.size()); }
};

}  // namespace hexmesh

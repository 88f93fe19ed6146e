// Items grouped by colour, the schedule of the colour-by-colour parallel loops (element
// chunks in assembly, row ranges in BlockMatrix products).
#pragma once

#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

// Items 0..n-1 grouped by colour, in item order within a colour: order lists them, the
// items of colour c at [start[c], start[c + 1]).
inline void group_by_colour(const std::vector<int>& colour, int colours, std::vector<Id>& start,
                            std::vector<Id>& order) {
    start.assign(colours + 1, 0);
    for (int c : colour) ++start[c + 1];
    for (int c = 0; c < colours; ++c) start[c + 1] += start[c];
    std::vector<Id> next(start.begin(), start.end() - 1);
    order.resize(colour.size());
    for (size_t k = 0; k < colour.size(); ++k) order[next[colour[k]]++] = Id(k);
}

}  // namespace hexmesh::untangle

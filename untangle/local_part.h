// The part of a problem around its inverted elements, which the local repair untangles on
// its own.
#pragma once

#include <vector>

#include "untangle/problem.h"

namespace hexmesh::untangle {

// The part of `problem` around its inverted elements (elements_of: per vertex, the elements
// it belongs to): vertices within `rings` element rings of them stay free (if they were), all
// others are fixed, and only the elements with a free vertex are kept. Returns false when
// that part is already the whole problem.
bool local_part(const Problem& problem, const std::vector<std::vector<Id>>& elements_of, int rings,
                Problem& part);

}  // namespace hexmesh::untangle

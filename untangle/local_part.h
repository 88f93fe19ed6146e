// The part of a problem around its inverted elements, which the local repair untangles on
// its own.
#pragma once

#include <vector>

#include "untangle/assembly.h"
#include "untangle/problem.h"

namespace hexmesh::untangle {

// Where a part sits in its whole problem: the whole's vertex of each of its vertices, and the
// stats of the whole's elements it leaves out (they have no free vertex: a solve of the part
// does not change them; min det +inf when there are none).
struct PartOf {
    std::vector<Id> global;
    ElementStats outside;
};

// The part of `problem` around its inverted elements (elements_of: per vertex, the elements
// it belongs to), as a problem of its own: vertices within `rings` element rings of them stay
// free (if they were), and only the elements with such a free vertex are kept, with their
// vertices, numbered from 0 (`of` maps them back). A solve of the part costs what the part
// holds, not the whole. Returns false when that part holds half the problem's elements or
// more, or no free vertex.
bool local_part(const Problem& problem, const std::vector<std::vector<Id>>& elements_of, int rings,
                Problem& part, PartOf& of);

}  // namespace hexmesh::untangle

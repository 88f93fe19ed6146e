// Certified validity of hex cells: the signs of their corner-tet determinants, exactly.
#pragma once

#include <array>
#include <vector>

#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Exact sign (+1, 0, -1) of det[a-c, b-c, d-c], by CGAL's exact orientation predicate.
int exact_orientation(const Vec3& c, const Vec3& a, const Vec3& b, const Vec3& d);

// Number of corner tets of one hex whose exact determinant is <= 0 (0..8).
int count_inverted_corner_tets(const std::array<Vec3, 8>& p);

struct InversionCount {
    Id corner_tets = 0;  // corner tets with exact det <= 0
    Id cells = 0;        // cells with at least one such corner tet
};

// Exact inversion counts over the whole mesh (parallel).
InversionCount count_inversions(const HexMesh& mesh);

// Ids of the cells with at least one corner tet of exact det <= 0, ascending.
std::vector<Id> find_inverted_cells(const HexMesh& mesh);

}  // namespace hexmesh

// Certified validity: signs of the corner-tet determinants by CGAL's exact orientation predicate.
//
// CGAL stays in this file. Epick's orientation is filtered: interval arithmetic first, exact
// arithmetic only when the sign is uncertain, so the answer is the sign of the determinant of
// the double coordinates as given, with no rounding error. It is thread safe.
#include "hexmesh/quality/validity.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "hexmesh/core/reference_hex.h"

namespace hexmesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

inline Point to_point(const Vec3& v) {
    return Point(v[0], v[1], v[2]);
}

}  // namespace

// CGAL::orientation(p, q, r, s) is POSITIVE when det[q-p, r-p, s-p] > 0 (checked on the unit
// cube in test_quality.cpp), so the corner tet (c, a, b, d) maps to orientation(c, a, b, d).
int exact_orientation(const Vec3& c, const Vec3& a, const Vec3& b, const Vec3& d) {
    switch (CGAL::orientation(to_point(c), to_point(a), to_point(b), to_point(d))) {
        case CGAL::POSITIVE:
            return 1;
        case CGAL::NEGATIVE:
            return -1;
        default:
            return 0;
    }
}

int count_inverted_corner_tets(const std::array<Vec3, 8>& p) {
    int inverted = 0;
    for (const auto& [c, a, b, d] : hex_corner_tets)
        if (exact_orientation(p[c], p[a], p[b], p[d]) <= 0) ++inverted;
    return inverted;
}

InversionCount count_inversions(const HexMesh& mesh) {
    // Integer sums: the result does not depend on how TBB splits the range.
    return tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, mesh.num_cells(), 4096), InversionCount{},
        [&](const tbb::blocked_range<Id>& r, InversionCount acc) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                const int n = count_inverted_corner_tets(mesh.corners(c));
                acc.corner_tets += n;
                acc.cells += n > 0;
            }
            return acc;
        },
        [](InversionCount x, const InversionCount& y) {
            x.corner_tets += y.corner_tets;
            x.cells += y.cells;
            return x;
        });
}

std::vector<Id> find_inverted_cells(const HexMesh& mesh) {
    std::vector<char> bad(static_cast<size_t>(mesh.num_cells()), 0);
    tbb::parallel_for(tbb::blocked_range<Id>(0, mesh.num_cells(), 4096),
                      [&](const tbb::blocked_range<Id>& r) {
                          for (Id c = r.begin(); c != r.end(); ++c)
                              bad[c] = count_inverted_corner_tets(mesh.corners(c)) > 0;
                      });
    std::vector<Id> ids;
    for (Id c = 0; c < mesh.num_cells(); ++c)
        if (bad[c]) ids.push_back(c);
    return ids;
}

}  // namespace hexmesh

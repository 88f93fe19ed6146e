#include <gtest/gtest.h>

#include <vector>

#include "grid_problem.h"
#include "untangle/assembly.h"
#include "untangle/local_part.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

namespace {

// A 16^3 grid with node (8, 8, 8) pushed 1.5 cells along x (its corner tets inverted) and the
// grid's corner node (0, 0, 0), fixed, pushed 1.5 cells inside, node (1, 1, 1) fixed too: the
// first hex has every node fixed and an inverted corner tet, which no solve can repair.
Problem two_faults() {
    std::vector<double> x;
    for (int i = 0; i <= 16; ++i) x.push_back(i);
    Problem p = test_support::tensor_grid_problem(x, x, x);
    p.points[8 + 17 * (8 + 17 * 8)] += Vec3(1.5, 0, 0);
    p.points[0] = Vec3(1.5, 1.5, 1.5);
    p.kinds[1 + 17 * (1 + 17 * 1)] = VertexKind::fixed;
    return p;
}

std::vector<std::vector<Id>> elements_of(const Problem& p) {
    std::vector<std::vector<Id>> of(p.points.size());
    for (Id e = 0; e < p.num_elements(); ++e)
        for (Id v : p.element(e)) of[v].push_back(e);
    return of;
}

}  // namespace

// The part around the inverted elements holds only its elements' vertices, each where it is
// in the whole; with the elements it leaves out (the blocked corner among them), it counts
// what the whole counts.
TEST(LocalPart, HoldsOnlyItsElementsVerticesAndCountsTheRestApart) {
    const Problem p = two_faults();
    Problem part;
    PartOf of;
    ASSERT_TRUE(local_part(p, elements_of(p), 2, part, of));
    ASSERT_EQ(of.global.size(), part.points.size());
    EXPECT_LT(part.points.size(), p.points.size() / 5);
    for (size_t v = 0; v < part.points.size(); ++v) {
        EXPECT_EQ(part.points[v], p.points[of.global[v]]);
        if (part.kinds[v] != VertexKind::fixed) {
            EXPECT_EQ(part.kinds[v], p.kinds[of.global[v]]);
        }
    }
    // the free vertices: node (8, 8, 8) and those within 2 element rings of its tets
    const Id free = Id(std::count(part.kinds.begin(), part.kinds.end(), VertexKind::interior));
    EXPECT_GT(free, 0);
    EXPECT_LT(free, Id(part.points.size()));
    const ElementStats whole = Assembly(p).stats(p.points);
    const ElementStats own = Assembly(part).stats(part.points);
    EXPECT_GE(of.outside.inverted, 1);  // the first hex's
    EXPECT_EQ(own.inverted + of.outside.inverted, whole.inverted);
    EXPECT_EQ(std::min(own.min_det, of.outside.min_det), whole.min_det);
    // every element of the part has a free vertex; the part is well under half the whole
    for (Id e = 0; e < part.num_elements(); ++e) {
        const ElementNodes n = part.element(e);
        const bool free_vertex = std::any_of(
            n.begin(), n.end(), [&](Id v) { return part.kinds[v] != VertexKind::fixed; });
        // a hex's corner tets come whole: its tets without a free vertex are there too
        if (!free_vertex) {
            EXPECT_TRUE(part.is_hex_corner(e));
        }
    }
    EXPECT_LT(part.num_elements(), p.num_elements() / 5);
}

// The part's geometry functions take its own vertex ids and answer as the whole's did for
// the same vertex.
TEST(LocalPart, GeometryFunctionsTakeThePartsVertexIds) {
    Problem p = two_faults();
    p.surface_normal = [](Id v, const Vec3&) { return Vec3(double(v), 0, 0); };
    p.project_to_surface = [](Id v, const Vec3&) { return Vec3(0, double(v), 0); };
    Problem part;
    PartOf of;
    ASSERT_TRUE(local_part(p, elements_of(p), 2, part, of));
    ASSERT_TRUE(bool(part.surface_normal) && bool(part.project_to_surface));
    EXPECT_FALSE(bool(part.edge_tangent));  // none in the whole: none in the part
    for (size_t v = 0; v < part.points.size(); ++v) {
        EXPECT_EQ(part.surface_normal(Id(v), part.points[v]).x(), double(of.global[v]));
        EXPECT_EQ(part.project_to_surface(Id(v), part.points[v]).y(), double(of.global[v]));
    }
}

// A part that would hold half the whole or more is refused (the whole is solved instead).
TEST(LocalPart, RefusesAPartOfHalfTheWhole) {
    const Problem p = two_faults();
    Problem part;
    PartOf of;
    EXPECT_FALSE(local_part(p, elements_of(p), 8, part, of));
    EXPECT_GE(part.num_elements(), p.num_elements() / 2);
}

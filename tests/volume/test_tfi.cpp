#include <gtest/gtest.h>

#include "volume/stretching.h"
#include "volume/tfi.h"

using namespace hexmesh;

namespace {

Block identity_block(Dims dims) {
    Block b{"b", dims, {}, {}};
    for (Id id = 0; id < dims.count(); ++id) b.node_ids.push_back(id);
    return b;
}

}  // namespace

TEST(Tfi, ReproducesAnAffineStretchedGridFromItsFaces) {
    const Dims dims{7, 5, 9};
    const Block block = identity_block(dims);
    const auto x = wall_distances(2.0, 6, WallLayers{0.05, 1.3, 3});
    const auto y = wall_distances(1.0, 4, WallLayers{});
    const auto z = wall_distances(3.0, 8, WallLayers{0.02, 1.1, 4});
    Mat3 A;
    A << 1.0, 0.3, 0.1, -0.2, 1.1, 0.0, 0.05, 0.2, 0.9;
    const Vec3 t(0.5, -1.0, 2.0);
    std::vector<Vec3> expected(dims.count()), points(dims.count(), Vec3::Constant(1e9));
    for (int k = 0; k < dims.nk; ++k)
        for (int j = 0; j < dims.nj; ++j)
            for (int i = 0; i < dims.ni; ++i) {
                const Id id = dims.flat(i, j, k);
                expected[id] = A * Vec3(x[i], y[j], z[k]) + t;
                const bool boundary = i == 0 || j == 0 || k == 0 || i == dims.ni - 1 ||
                                      j == dims.nj - 1 || k == dims.nk - 1;
                if (boundary) points[id] = expected[id];
            }
    fill_interior_tfi(block, points);
    for (Id id = 0; id < dims.count(); ++id)
        EXPECT_LT((points[id] - expected[id]).norm(), 1e-12) << "node " << id;
}

TEST(Tfi, CarriesTheInteriorWithItsBoundary) {
    // A stretched, sheared block: a uniform shift of its boundary shifts every node by the
    // same amount; moving one boundary node moves the nodes near it most.
    const Dims dims{6, 5, 7};
    const Block block = identity_block(dims);
    std::vector<Vec3> before(dims.count());
    for (int k = 0; k < dims.nk; ++k)
        for (int j = 0; j < dims.nj; ++j)
            for (int i = 0; i < dims.ni; ++i)
                before[dims.flat(i, j, k)] =
                    Vec3(i * i * 0.1 + 0.2 * j, j + 0.05 * k * k, k * 0.7 - 0.1 * i);
    std::vector<Vec3> points = before;
    const Vec3 d(0.3, -0.2, 0.5);
    for (Id v = 0; v < dims.count(); ++v) {
        const int i = int(v % dims.ni), j = int(v / dims.ni % dims.nj),
                  k = int(v / (Id(dims.ni) * dims.nj));
        if (i == 0 || j == 0 || k == 0 || i == dims.ni - 1 || j == dims.nj - 1 || k == dims.nk - 1)
            points[v] += d;
    }
    carry_interior_tfi(block, before, points);
    for (Id v = 0; v < dims.count(); ++v) EXPECT_LT((points[v] - before[v] - d).norm(), 1e-12) << v;

    points = before;
    points[dims.flat(0, 2, 3)] += Vec3(0.2, 0, 0);
    carry_interior_tfi(block, before, points);
    const double near = (points[dims.flat(1, 2, 3)] - before[dims.flat(1, 2, 3)]).norm();
    const double far = (points[dims.flat(4, 2, 3)] - before[dims.flat(4, 2, 3)]).norm();
    EXPECT_GT(near, 0.05);
    EXPECT_LT(far, near);
    EXPECT_EQ(points[dims.flat(5, 2, 3)], before[dims.flat(5, 2, 3)]);  // boundary: left
}

TEST(Tfi, LeavesBoundaryNodesUntouched) {
    const Dims dims{4, 4, 4};
    const Block block = identity_block(dims);
    std::vector<Vec3> points(dims.count());
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i)  // a curved boundary: z bulges with x
                points[dims.flat(i, j, k)] = Vec3(i, j, k + 0.1 * i * i);
    const auto before = points;
    fill_interior_tfi(block, points);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i)
                if (i % 3 == 0 || j % 3 == 0 || k % 3 == 0) {
                    EXPECT_EQ(points[dims.flat(i, j, k)], before[dims.flat(i, j, k)]);
                }
}

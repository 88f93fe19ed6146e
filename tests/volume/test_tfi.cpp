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

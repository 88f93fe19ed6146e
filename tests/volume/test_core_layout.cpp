#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>

#include "grid_checks.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "surface/csg.h"
#include "volume/axial_creases.h"
#include "volume/axial_rings.h"
#include "volume/core_layout.h"
#include "volume/cube_sphere.h"

using namespace hexmesh;

namespace {

// The core's blocks as a hex mesh over its cube coordinates.
HexMesh core_mesh(const CoreLayout& core) {
    BlockGrid grid;
    grid.points = core.t;
    grid.kinds.assign(core.t.size(), VertexKind::interior);
    grid.blocks = core.blocks;
    return to_hex_mesh(grid);
}

}  // namespace

TEST(CoreLayout, AxialCoreIsAConformingRightHandedPrismFilledByItsPieces) {
    const int n = 8;
    for (const int frame : {0, 2}) {
        for (const int axis : {0, 2}) {
            const AxialRings rings = even_axial_rings(axis, 3, axial_frame_edge(n, frame));
            const CoreLayout core = axial_core(n, frame, rings);
            EXPECT_EQ(core.blocks.size(), frame > 0 ? 13u : 5u);
            const HexMesh mesh = core_mesh(core);
            EXPECT_EQ(measure_quality(mesh).inverted_corner_tets, 0) << frame << " " << axis;
            // Shared faces match; the faces used once are exactly the wall faces, which lie on
            // the cube's surface and cover each of its faces' area.
            const auto faces = test_support::count_faces(mesh);
            EXPECT_EQ(faces.over_shared, 0);
            Id wall_quads = 0;
            std::array<Id, 6> per_side{};
            for (const CoreLayout::WallFace& f : core.wall_faces) {
                const Block& b = core.blocks[f.block];
                const int normal = f.face / 2;
                const Id quads =
                    Id(b.nodes[normal == 0 ? 1 : 0] - 1) * (b.nodes[normal == 2 ? 1 : 2] - 1);
                wall_quads += quads;
                per_side[f.side] += quads;
                const CubePatch& side = cube_patches[f.side];
                for (int k = 0; k < b.nodes.nk; ++k)
                    for (int j = 0; j < b.nodes.nj; ++j)
                        for (int i = 0; i < b.nodes.ni; ++i) {
                            const int at[3] = {i, j, k};
                            if (at[normal] != (f.face % 2 ? b.nodes[normal] - 1 : 0)) continue;
                            EXPECT_NEAR(core.t[b.node(i, j, k)][side.axis], side.max_side ? 1 : -1,
                                        1e-12);
                        }
            }
            EXPECT_EQ(faces.boundary, wall_quads);
            // The sides along the axis have n x n cells, as the one-block core's; the ends the
            // column, rings and frame.
            const Id m = n - 2 * frame;
            for (int side = 0; side < 6; ++side)
                EXPECT_EQ(per_side[side],
                          side / 2 == axis ? m * m + 4 * 3 * m + 4 * frame * m + 4 * frame * frame
                                           : Id(n) * n)
                    << side;
        }
    }
}

TEST(CoreLayout, RingsAreFittedToTheCirclesOfACylinderOnABox) {
    // Rays from the origin through the box's top face z = 0.6 at distance w from the axis
    // meet the rim for w = 0.6 * 0.6 / 1.2 = 0.3 and the junction circle at w = 0.6.
    const Body body = test_support::box_with_cylinder();
    const Vec3 half(1.0, 1.0, 0.6);
    const auto ray = [&](const Vec3& t) { return cube_ray(t, half); };
    const double outer = axial_frame_edge(16, 1);
    const AxialCreases creases = find_axial_creases(*body, Vec3::Zero(), ray, 2, outer, 0.05);
    ASSERT_EQ(creases.radius.size(), 2u);
    for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(creases.seen[k], 4);  // the four half-lines of the top face
        EXPECT_NEAR(creases.reach[k], creases.radius[k], 1e-9);  // circles
    }
    std::array<AxialCreases, 3> around;
    for (int axis = 0; axis < 3; ++axis)
        around[axis] = find_axial_creases(*body, Vec3::Zero(), ray, axis, outer, 0.05);
    EXPECT_EQ(choose_axis(around), 2);
    const AxialRings rings = fit_axial_rings(creases, 2, 8, outer);
    ASSERT_EQ(rings.cells(), 8);
    EXPECT_DOUBLE_EQ(rings.radius.back(), outer);
    for (const double circle : {0.3, 0.6}) {
        int s = 0;
        while (s < 8 && std::abs(rings.radius[s] - circle) > 1e-9) ++s;
        ASSERT_LT(s, 8) << "no ring on the circle at " << circle;
        EXPECT_NEAR(rings.roundness[s], 1.0, 1e-12);
    }
    EXPECT_NEAR(rings.column(), 0.15, 0.005);
    for (int s = 0; s < 8; ++s) EXPECT_LT(rings.radius[s], rings.radius[s + 1]);
    EXPECT_EQ(rings.roundness.front(), 0.0);
    EXPECT_EQ(rings.roundness.back(), 0.0);

    // A smooth body has no creases to fit: the rings are even.
    const Sphere sphere(Vec3::Zero(), 1.0);
    const AxialCreases none = find_axial_creases(sphere, Vec3::Zero(), ray, 2, outer, 0.05);
    EXPECT_TRUE(none.radius.empty());
    EXPECT_EQ(fit_axial_rings(none, 2, 8, outer).radius, even_axial_rings(2, 8, outer).radius);
}

TEST(CoreLayout, ASquareCreaseGetsASquareRingButNoAxis) {
    // A smaller box on a box: its square creases are square rings around z, but one core
    // block's patch has lines along them, corners included: no axis is chosen.
    const Body body = std::make_shared<Csg>(
        CsgOp::Union,
        std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(1.0, 1.0, 0.6)),
                          std::make_shared<Box>(Vec3(0, 0, 0.6), Vec3(0.4, 0.4, 0.3))});
    const Vec3 half(1.0, 1.0, 0.6);
    const auto ray = [&](const Vec3& t) { return cube_ray(t, half); };
    const double outer = axial_frame_edge(16, 1);
    std::array<AxialCreases, 3> creases;
    for (int axis = 0; axis < 3; ++axis)
        creases[axis] = find_axial_creases(*body, Vec3::Zero(), ray, axis, outer, 0.05);
    EXPECT_EQ(choose_axis(creases), -1);
    // Seen from the origin through z = 0.6: the top box's top square (z = 0.9) at 0.4 * 0.6 /
    // 0.9, its base at 0.4.
    ASSERT_EQ(creases[2].radius.size(), 2u);
    EXPECT_NEAR(creases[2].radius[0], 0.4 * 0.6 / 0.9, 1e-9);
    const double w = creases[2].radius[1];
    EXPECT_NEAR(w, 0.4, 1e-9);
    for (int k = 0; k < 2; ++k)
        EXPECT_NEAR(creases[2].reach[k], std::sqrt(2.0) * creases[2].radius[k], 1e-9);
    const AxialRings rings = fit_axial_rings(creases[2], 2, 8, outer);
    int s = 0;
    while (s < 8 && std::abs(rings.radius[s] - w) > 1e-9) ++s;
    ASSERT_LT(s, 8);
    EXPECT_EQ(rings.roundness[s], 0.0);

    const Sphere sphere(Vec3::Zero(), 1.0);
    for (int axis = 0; axis < 3; ++axis)
        creases[axis] = find_axial_creases(sphere, Vec3::Zero(), ray, axis, outer, 0.05);
    EXPECT_EQ(choose_axis(creases), -1);
}

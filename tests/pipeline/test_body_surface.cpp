#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "hexmesh/pipeline/body_surface.h"
#include "hexmesh/pipeline/sphere_map.h"
#include "surface/analytic.h"
#include "surface/csg.h"

using namespace hexmesh;

namespace {

// V - E + F of a surface whose every edge two triangles share (checked): 2 for genus 0.
int euler_characteristic(const TriangleSurface& s) {
    const auto uses = edge_uses(s.triangles);
    for (const auto& [edge, n] : uses) EXPECT_EQ(n, 2) << "edge " << edge;
    std::set<int> used;
    for (const auto& t : s.triangles) used.insert(t.begin(), t.end());
    return int(used.size()) - int(uses.size()) + int(s.triangles.size());
}

// An L of two bars, 1 x 0.3 x 0.3 and 0.3 x 1 x 0.3: not star-shaped around the centre of
// its bounds.
Body ell() {
    return std::make_shared<Csg>(
        CsgOp::Union,
        std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3(0.5, 0.15, 0.15)),
                          std::make_shared<Box>(Vec3(-0.35, 0.35, 0), Vec3(0.15, 0.5, 0.15))});
}

}  // namespace

TEST(BodySurface, ASphereContoursToAClosedSurfaceOnItsLevelZero) {
    const Sphere sphere(Vec3(0.1, -0.2, 0.3), 0.5);
    const TriangleSurface s = contour_body(sphere, 48);
    EXPECT_EQ(euler_characteristic(s), 2);
    const double step = 1.0 / 48;
    for (const Vec3& p : s.points) EXPECT_LT(std::abs(sphere.value(p)), 0.1 * step);
    // Facing outwards, enclosing the ball's volume to the lattice's chord error.
    EXPECT_NEAR(signed_volume(s, Vec3(0.1, -0.2, 0.3)), 4 * M_PI / 3 * 0.125, 0.01 * 0.52);
}

TEST(BodySurface, AnEllContoursToOnePieceOfGenusZeroThatMapsOntoTheSphere) {
    const Body body = ell();
    const TriangleSurface s = contour_body(*body, 96);
    EXPECT_EQ(euler_characteristic(s), 2);
    // Volume 0.09 + 0.09 - 0.3 x 0.3 x 0.3 shared.
    EXPECT_NEAR(signed_volume(s), 0.153, 0.005);
    EXPECT_EQ(map_to_sphere(s).inverted(), 0);
}

TEST(BodySurface, ATorusContoursToGenusOneWhichTheSphereMapRefuses) {
    const Torus torus(Vec3::Zero(), 0.4, 0.15);
    const TriangleSurface s = contour_body(torus, 64);
    EXPECT_EQ(euler_characteristic(s), 0);
    EXPECT_THROW(map_to_sphere(s), std::invalid_argument);
}

TEST(BodySurface, ABodyWithNoInsideIsRefused) {
    // A box less a larger one: its bounds are the first box's, nothing is inside.
    const Csg nothing(CsgOp::Difference,
                      std::vector<Body>{std::make_shared<Box>(Vec3::Zero(), Vec3::Constant(0.5)),
                                        std::make_shared<Box>(Vec3::Zero(), Vec3::Constant(1))});
    try {
        contour_body(nothing, 96);
        FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("no point of the body is inside"), std::string::npos)
            << e.what();
    }
}

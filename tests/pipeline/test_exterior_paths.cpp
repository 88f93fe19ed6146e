// Lines of an exterior grid along the gradient lines of a potential (exterior_paths).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "hexmesh/pipeline/exterior_paths.h"
#include "volume/cube_sphere.h"

using namespace hexmesh;

namespace {

// F = 1 - 1/|x| outside the unit ball (harmonic, 0 on the sphere, 1 far away), 0 inside it;
// with `plateau`, also 0 above z = 0.5, where its gradient vanishes.
class BallPotential : public ImplicitFunction {
public:
    explicit BallPotential(bool plateau = false) : plateau_(plateau) {}
    double value(const Vec3& p) const override {
        if (flat(p)) return 0;
        return 1 - 1 / p.norm();
    }
    Vec3 gradient(const Vec3& p) const override {
        if (flat(p)) return Vec3::Zero();
        return p / std::pow(p.norm(), 3);
    }
    Box3 bounds() const override { return {Vec3::Constant(-1), Vec3::Constant(1)}; }

private:
    bool flat(const Vec3& p) const { return p.norm() <= 1 || (plateau_ && p.z() > 0.5); }
    bool plateau_;
};

std::vector<Vec3> unit_sphere_wall(int n) {
    const CubeSurfaceLattice lattice = make_cube_surface_lattice(n);
    std::vector<Vec3> wall(lattice.size());
    for (Id s = 0; s < lattice.size(); ++s)
        wall[s] = 1.0001 * cube_sphere_ray(lattice.points[s], n, Vec3::Ones()).normalized();
    return wall;
}

}  // namespace

TEST(ExteriorPaths, LinesOfABallsPotentialAreItsRaysUpToTheLevel) {
    const int n = 4;
    const std::vector<Vec3> wall = unit_sphere_wall(n);
    const WallPaths paths = exterior_paths(BallPotential(), wall, 0.5, n, Vec3::Zero(), {});
    ASSERT_EQ(paths.lines.size(), wall.size());
    for (size_t s = 0; s < wall.size(); ++s) {
        // F = 0.5 at |x| = 2, reached along the ray through the wall point (the last step
        // lands on the level by linear interpolation of F: 1e-5 off for steps of 0.125).
        EXPECT_NEAR(paths.lines[s].back().norm(), 2, 1e-4) << s;
        EXPECT_NEAR(paths.lines[s].back().normalized().dot(wall[s].normalized()), 1, 1e-9) << s;
        EXPECT_NEAR(paths.levels[s].back(), 0.5, 1e-9) << s;
        EXPECT_NEAR(paths.far_directions[s].dot(wall[s].normalized()), 1, 1e-3) << s;
    }
}

TEST(ExteriorPaths, ALineThatStopsShortOfTheLevelIsRefusedWithItsPoint) {
    const int n = 4;
    try {
        exterior_paths(BallPotential(true), unit_sphere_wall(n), 0.5, n, Vec3::Zero(), {});
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("gradient line from the wall point ("), std::string::npos) << what;
        EXPECT_NE(what.find("short of the far level 0.5"), std::string::npos) << what;
    }
}

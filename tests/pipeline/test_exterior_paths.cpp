// Lines of an exterior grid along the gradient lines of a potential (exterior_paths).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hexmesh/pipeline/exterior_paths.h"
#include "hexmesh/pipeline/spread_on_levels.h"
#include "surface/analytic.h"
#include "volume/cube_sphere.h"

using namespace hexmesh;

namespace {

// F = 1 - 1/|x| outside the unit ball (harmonic, 0 on the sphere, 1 far away), F < 0 inside.
// Flat::everywhere: 0 everywhere, its gradient nowhere non-zero. Flat::pocket: constant in a
// ball of radius 0.1 round (0, 0, 1.3), on the line of the top wall node, its gradient zero
// there; Flat::lying_pocket: the same with a gradient towards the pocket's centre, which steps
// follow to and fro without rising.
enum class Flat { nowhere, everywhere, pocket, lying_pocket };
class BallPotential : public ImplicitFunction {
  public:
    explicit BallPotential(Flat flat = Flat::nowhere) : flat_(flat) {}
    double value(const Vec3& p) const override {
        if (flat_ == Flat::everywhere) return 0;
        if (in_pocket(p)) return 1 - 1 / 1.2;
        return 1 - 1 / p.norm();
    }
    Vec3 gradient(const Vec3& p) const override {
        if (flat_ == Flat::everywhere || p.norm() <= 1) return Vec3::Zero();
        if (in_pocket(p))
            return flat_ == Flat::lying_pocket ? Vec3(pocket_centre() - p) : Vec3(Vec3::Zero());
        return p / std::pow(p.norm(), 3);
    }
    Box3 bounds() const override { return {Vec3::Constant(-1), Vec3::Constant(1)}; }
    static Vec3 pocket_centre() { return {0, 0, 1.3}; }
    static bool near_pocket(const Vec3& p, double margin) {
        return (p - pocket_centre()).norm() < 0.1 + margin;
    }

  private:
    bool in_pocket(const Vec3& p) const {
        return (flat_ == Flat::pocket || flat_ == Flat::lying_pocket) && near_pocket(p, 0);
    }
    Flat flat_;
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

TEST(ExteriorPaths, WithDirectionsEveryLineIsAFibreAndRoundABallARay) {
    // The unit ball's lattice potential and radial directions: every line follows its fibre,
    // which is the ray through its wall node (within 2 degrees on a lattice of 24), up to the
    // level.
    const int n = 4;
    const Sphere body(Vec3::Zero(), 1);
    ExteriorPotentialOptions o;
    o.resolution = 24;
    o.margin = 0.6;
    const ExteriorPotential potential(body, o);
    const HarmonicDirections theta(
        body, [](const Vec3& x) { return Vec3(x.normalized()); }, Vec3::Zero(), o);
    const std::vector<Vec3> wall = unit_sphere_wall(n);
    const WallPaths paths =
        exterior_paths(potential, wall, 0.5, n, Vec3::Zero(), {}, nullptr, &theta);
    EXPECT_EQ(paths.fibres, Id(wall.size()));
    for (size_t s = 0; s < wall.size(); ++s) {
        EXPECT_NEAR(paths.levels[s].back(), 0.5, 1e-9) << s;
        for (const Vec3& x : paths.lines[s])
            EXPECT_GT(x.normalized().dot(wall[s].normalized()), std::cos(2 * M_PI / 180)) << s;
    }
    EXPECT_EQ(exterior_paths(potential, wall, 0.5, n, Vec3::Zero(), {}).fibres, 0);
}

TEST(ExteriorPaths, ALineThatStopsShortOfTheLevelIsRefusedWithItsPoint) {
    const int n = 4;
    try {
        exterior_paths(BallPotential(Flat::everywhere), unit_sphere_wall(n), 0.5, n, Vec3::Zero(),
                       {});
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("gradient line from the wall point ("), std::string::npos) << what;
        EXPECT_NE(what.find("short of the far level 0.5"), std::string::npos) << what;
    }
}

TEST(ExteriorPaths, ALineClimbsOutOfAPocketWhereTheGradientVanishes) {
    // As in a gap about as narrow as a potential's lattice: the top node's line meets the
    // pocket, where a gradient step goes nowhere; it is traced again, climbing to a higher point
    // around and on, and lands on the level. Lines that never come near the pocket are the
    // plain potential's, point for point.
    const int n = 4;
    const std::vector<Vec3> wall = unit_sphere_wall(n);
    const WallPaths plain = exterior_paths(BallPotential(), wall, 0.5, n, Vec3::Zero(), {});
    for (const Flat flat : {Flat::pocket, Flat::lying_pocket}) {
        const BallPotential potential(flat);
        const WallPaths paths = exterior_paths(potential, wall, 0.5, n, Vec3::Zero(), {});
        int through_pocket = 0, unchanged = 0;
        for (size_t s = 0; s < wall.size(); ++s) {
            EXPECT_NEAR(paths.levels[s].back(), 0.5, 1e-9) << s;
            // The last gradient step lands by linear interpolation of F: within F'' h^2 / 8.
            EXPECT_NEAR(potential.value(paths.lines[s].back()), 0.5, 1e-3) << s;
            bool near = false;
            for (const Vec3& x : plain.lines[s]) near = near || BallPotential::near_pocket(x, 0.05);
            for (const Vec3& x : paths.lines[s]) through_pocket += BallPotential::near_pocket(x, 0);
            if (!near) {
                EXPECT_EQ(paths.lines[s], plain.lines[s]) << s;
                ++unchanged;
            }
        }
        EXPECT_GT(through_pocket, 0);  // the top line did enter it
        EXPECT_GE(unchanged, int(wall.size()) - 1);
    }
}

namespace {

// F = (1/|x| - 1) / (1/0.2 - 1) inside the unit ball: 0 on the sphere, 1 on the ball of radius
// 0.2 (the interior potential of a sphere with its source there), rising inwards.
class InnerBallPotential : public ImplicitFunction {
  public:
    double value(const Vec3& p) const override { return (1 / p.norm() - 1) / (1 / 0.2 - 1); }
    Vec3 gradient(const Vec3& p) const override {
        return -p / std::pow(p.norm(), 3) / (1 / 0.2 - 1);
    }
    Box3 bounds() const override { return {Vec3::Constant(-1), Vec3::Constant(1)}; }
};

}  // namespace

TEST(InteriorPaths, LinesOfABallsInteriorPotentialAreItsRaysInToTheLevel) {
    const int n = 4;
    std::vector<Vec3> wall = unit_sphere_wall(n);
    for (Vec3& x : wall) x /= 1.0002;  // just inside
    const WallPaths paths = interior_paths(InnerBallPotential(), wall, 0.5, n, Vec3::Zero());
    ASSERT_EQ(paths.lines.size(), wall.size());
    EXPECT_TRUE(paths.far_directions.empty());
    // F = 0.5 at 1/|x| = 3, |x| = 1/3; the last step of 0.125 lands there by linear
    // interpolation of F, which is curved (1/|x|): up to F'' h^2 / 8 / F' = 0.012 off in |x|.
    for (size_t s = 0; s < wall.size(); ++s) {
        EXPECT_NEAR(paths.lines[s].back().norm(), 1.0 / 3, 0.012) << s;
        EXPECT_NEAR(paths.lines[s].back().normalized().dot(wall[s].normalized()), 1, 1e-9) << s;
        EXPECT_NEAR(paths.levels[s].back(), 0.5, 1e-9) << s;
    }
}

TEST(InteriorPaths, ALineThatStopsShortOfTheLevelIsLeftAsItsWallPoint) {
    // The ball's interior potential capped at 0.3 (flat beyond, as in a long limb where it
    // decays below its solve's noise): every line rises from its wall point, then stops short
    // of the level 0.5, and is left as its wall point for the grid to run straight from.
    class Capped : public ImplicitFunction {
      public:
        double value(const Vec3& p) const override { return std::min(ball_.value(p), 0.3); }
        Vec3 gradient(const Vec3& p) const override {
            return ball_.value(p) >= 0.3 ? Vec3(Vec3::Zero()) : ball_.gradient(p);
        }
        Box3 bounds() const override { return ball_.bounds(); }

      private:
        InnerBallPotential ball_;
    };
    const int n = 4;
    std::vector<Vec3> wall = unit_sphere_wall(n);
    for (Vec3& x : wall) x /= 1.0002;
    // Traced as interior_paths traces them, the lines do rise before they stop.
    std::vector<double> levels;
    const std::vector<Vec3> risen = gradient_line_up(Capped(), wall[0], 0.5, 0.125, levels, true);
    EXPECT_GT(risen.size(), 2u);
    EXPECT_NEAR(levels.back(), 0.3, 1e-9);
    const WallPaths paths = interior_paths(Capped(), wall, 0.5, n, Vec3::Zero());
    ASSERT_EQ(paths.lines.size(), wall.size());
    for (size_t s = 0; s < wall.size(); ++s) {
        ASSERT_EQ(paths.lines[s].size(), 1u) << s;
        EXPECT_EQ(paths.lines[s][0], wall[s]) << s;
    }
}

namespace {

// The smallest sine of a corner angle of the lattice's quads at these points, seen from
// outside the unit ball (negative: a quad folded over).
double smallest_corner_sine(const std::vector<Vec3>& x, int n) {
    double smallest = 1;
    for (const auto& q : cube_surface_quads(make_cube_surface_lattice(n)))
        for (int c = 0; c < 4; ++c) {
            const Vec3 a = x[q[(c + 1) % 4]] - x[q[c]], b = x[q[(c + 3) % 4]] - x[q[c]];
            smallest =
                std::min(smallest, a.cross(b).dot(x[q[c]].normalized()) / (a.norm() * b.norm()));
        }
    return smallest;
}

std::vector<Vec3> ends(const WallPaths& paths) {
    std::vector<Vec3> x;
    for (const auto& line : paths.lines) x.push_back(line.back());
    return x;
}

}  // namespace

TEST(SpreadOnLevels, SoundLinesAreLeftAsTheyAre) {
    const int n = 8;
    const std::vector<Vec3> wall = unit_sphere_wall(n);
    WallPaths paths = exterior_paths(BallPotential(), wall, 0.5, n, Vec3::Zero(), {});
    const WallPaths plain = paths;
    const LevelSpreading done = spread_on_levels(BallPotential(), paths, {});
    EXPECT_GT(done.levels, 3);
    EXPECT_EQ(done.levels_spread + done.levels_left, 0);
    EXPECT_EQ(done.lines_moved, 0);
    EXPECT_EQ(paths.lines, plain.lines);
}

TEST(SpreadOnLevels, AFoldTheWallCarriesOutIsSpreadOutOnTheFirstLevel) {
    // Two neighbouring wall nodes swapped: the quads between them are folded on every level
    // the radial gradient lines reach. Spread on the first level, the nodes go on up unfolded;
    // the lines of nodes far from the fold are the gradient lines, point for point.
    const int n = 8;
    const CubeSurfaceLattice lattice = make_cube_surface_lattice(n);
    std::vector<Vec3> wall = unit_sphere_wall(n);
    const Id a = lattice.number_of(lattice.patch_point(cube_patches[0], 3, 3));
    const Id b = lattice.number_of(lattice.patch_point(cube_patches[0], 4, 3));
    std::swap(wall[a], wall[b]);
    const BallPotential potential;
    WallPaths paths = exterior_paths(potential, wall, 0.5, n, Vec3::Zero(), {});
    const WallPaths plain = paths;
    ASSERT_LT(smallest_corner_sine(ends(plain), n), 0);
    const LevelSpreading done = spread_on_levels(potential, paths, {});
    EXPECT_GE(done.levels_spread, 1);
    EXPECT_EQ(done.levels_left, 0);
    EXPECT_GT(done.lines_moved, 0);
    EXPECT_GT(smallest_corner_sine(ends(paths), n), 0.1);
    Id unchanged = 0;
    for (size_t s = 0; s < wall.size(); ++s) {
        EXPECT_EQ(paths.lines[s].front(), wall[s]) << s;
        EXPECT_TRUE(std::is_sorted(paths.levels[s].begin(), paths.levels[s].end())) << s;
        EXPECT_NEAR(paths.levels[s].back(), 0.5, 1e-9) << s;
        EXPECT_NEAR(potential.value(paths.lines[s].back()), 0.5, 1e-3) << s;
        unchanged += paths.lines[s] == plain.lines[s];
    }
    EXPECT_EQ(Id(wall.size()) - unchanged, done.lines_moved);
    EXPECT_GT(unchanged, Id(wall.size()) / 2);
}

TEST(ExteriorPaths, AFibreOfTheDirectionsRunsFromTheWallPointOfImageDToTheBoxInDirectionD) {
    // Round a sphere, directions that are the radial ones turned by 60 degrees about z on the
    // body and radial on the box: the fibre from the wall point whose image is d turns with
    // the field on its way out and ends near the box in the direction d.
    const Sphere body(Vec3::Zero(), 0.5);
    ExteriorPotentialOptions o;
    o.resolution = 32;
    o.margin = 0.6;
    const ExteriorPotential potential(body, o);
    const Mat3 turn = Eigen::AngleAxisd(M_PI / 3, Vec3::UnitZ()).toRotationMatrix();
    const HarmonicDirections theta(
        body, [&](const Vec3& x) { return Vec3(turn * x.normalized()); }, Vec3::Zero(), o);
    for (const Vec3& wall : {Vec3(0.5, 0, 0), Vec3(0, -0.3, 0.4), Vec3(0.3, 0.3, 0.3)}) {
        const Vec3 p = 0.5 * wall.normalized();
        std::vector<double> levels;
        const std::vector<Vec3> line =
            direction_line_up(potential, theta, p, 0.97, 0.01, 0.0, levels);
        ASSERT_GE(line.size(), 2u);
        EXPECT_NEAR(levels.back(), 0.97, 1e-9);
        EXPECT_TRUE(std::is_sorted(levels.begin(), levels.end()));
        const Vec3 d = theta.value(p).normalized();
        EXPECT_LT(d.dot(turn * p.normalized()), 1.0 + 1e-9);
        EXPECT_GT(d.dot(turn * p.normalized()), std::cos(3 * M_PI / 180));
        // Every point of the line on the fibre of d; its end within 5 degrees of d seen from
        // the centre.
        for (const Vec3& x : line)
            EXPECT_GT(theta.value(x).normalized().dot(d), std::cos(1 * M_PI / 180));
        EXPECT_GT(line.back().normalized().dot(d), std::cos(5 * M_PI / 180))
            << "ends at " << line.back().transpose() << ", d " << d.transpose();
    }
}

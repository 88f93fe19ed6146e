#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "volume/stretching.h"

using namespace hexmesh;

TEST(WallDistances, LayersFollowTheLawAndTheLineIsFilled) {
    const WallLayers law{0.01, 1.2, 5};
    const auto d = wall_distances(1.0, 12, law);
    ASSERT_EQ(d.size(), 13u);
    EXPECT_DOUBLE_EQ(d[0], 0.0);
    EXPECT_DOUBLE_EQ(d[12], 1.0);
    EXPECT_NEAR(d[1] - d[0], 0.01, 1e-15);
    for (int m = 1; m < 5; ++m)
        EXPECT_NEAR((d[m + 1] - d[m]) / (d[m] - d[m - 1]), 1.2, 1e-12) << "layer " << m;
    for (int m = 0; m < 12; ++m) EXPECT_GT(d[m + 1], d[m]);
    // Beyond the layers the cells keep growing geometrically with one ratio.
    const double q = (d[7] - d[6]) / (d[6] - d[5]);
    for (int m = 6; m < 12; ++m) EXPECT_NEAR((d[m + 1] - d[m]) / (d[m] - d[m - 1]), q, 1e-9);
}

TEST(WallDistances, UniformWithoutLayers) {
    const auto d = wall_distances(2.0, 4, WallLayers{});
    for (int m = 0; m <= 4; ++m) EXPECT_DOUBLE_EQ(d[m], 0.5 * m);
}

TEST(WallDistances, RefusesLayersThatDoNotFitNamingWhere) {
    EXPECT_THROW(wall_distances(0.01, 10, WallLayers{0.01, 1.2, 5}), std::invalid_argument);
    EXPECT_THROW(wall_distances(1.0, 5, WallLayers{0.01, 1.2, 5}), std::invalid_argument);
    const Vec3 wall(0.25, -1, 3);
    try {
        wall_distances(0.03, 10, WallLayers{0.01, 1.2, 5}, &wall);
        ADD_FAILURE() << "5 layers 0.0744 thick fitted a line of length 0.03";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("boundary layer of 5 layers (0.07442 thick) does not "
                                             "fit the wall-normal line of 10 cells and length "
                                             "0.03 from the wall at (0.25, -1, 3)"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GeometricRatio, SolvesTheSeries) {
    const double q = geometric_ratio(0.1, 6, 2.0);
    double s = 0, p = 1;
    for (int j = 0; j < 6; ++j) s += (p *= q);
    EXPECT_NEAR(0.1 * s, 2.0, 1e-12);
    EXPECT_NEAR(geometric_ratio(1.0, 3, 3.0), 1.0, 1e-12);
}

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

// Where the line is too short for the whole layer (a thin part of the body), it takes the most
// layers of the law that fill at most half of it and leave a cell beyond: the first height and
// the growth ratio are kept, only the count is cut.
TEST(WallDistances, ThinLinesTakeFewerLayersOfTheSameHeights) {
    const WallLayers law{0.01, 1.2, 5};  // 0.0744 thick
    EXPECT_EQ(layers_that_fit(1.0, 12, law), 5);
    EXPECT_EQ(layers_that_fit(0.0745, 12, law), 5);  // thinner than the line: all of it
    EXPECT_EQ(layers_that_fit(0.0744, 12, law), 3);  // 0.0364 <= 0.0372 < 0.05368
    EXPECT_EQ(layers_that_fit(0.03, 10, law), 1);    // 0.01 <= 0.015 < 0.022
    EXPECT_EQ(layers_that_fit(1.0, 5, law), 4);      // no cell left beyond 5: 4
    EXPECT_EQ(layers_that_fit(0.0199, 10, law), 0);  // not even the first in half
    EXPECT_EQ(layers_that_fit(1.0, 12, WallLayers{}), 0);
    const auto d = wall_distances(0.0744, 12, law);
    ASSERT_EQ(d.size(), 13u);
    EXPECT_NEAR(d[1], 0.01, 1e-15);
    EXPECT_NEAR(d[2] - d[1], 0.012, 1e-15);
    EXPECT_NEAR(d[3] - d[2], 0.0144, 1e-15);
    EXPECT_DOUBLE_EQ(d[12], 0.0744);
    for (int m = 0; m < 12; ++m) EXPECT_GT(d[m + 1], d[m]);
    const double q = (d[5] - d[4]) / (d[4] - d[3]);  // one ratio beyond the three layers
    for (int m = 5; m < 12; ++m) EXPECT_NEAR((d[m + 1] - d[m]) / (d[m] - d[m - 1]), q, 1e-9);
}

TEST(WallDistances, RefusesALineWithoutRoomForTheFirstLayerNamingWhere) {
    EXPECT_THROW(wall_distances(0.0199, 10, WallLayers{0.01, 1.2, 5}), std::invalid_argument);
    EXPECT_NO_THROW(wall_distances(0.02, 10, WallLayers{0.01, 1.2, 5}));
    const Vec3 wall(0.25, -1, 3);
    try {
        wall_distances(0.015, 10, WallLayers{0.01, 1.2, 5}, &wall);
        ADD_FAILURE() << "a first layer of 0.01 fitted half a line of length 0.015";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("boundary layer of 5 layers (0.07442 thick) does not "
                                             "fit the wall-normal line of 10 cells and length "
                                             "0.015 from the wall at (0.25, -1, 3), not even its "
                                             "first layer (0.01) in half of it"),
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

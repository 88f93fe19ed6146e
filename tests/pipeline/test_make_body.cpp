#include <gtest/gtest.h>

#include <cmath>

#include "hexmesh/pipeline/make_body.h"

using namespace hexmesh;

TEST(MakeBody, TransformedSphereIsTheMovedSphere) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}, "scale": 2,
        "translate": [1, 0, 0], "rotate": {"axis": [0, 0, 1], "degrees": 90}}})", "c.json");
    const Body body = make_body(c.geometry);
    EXPECT_NEAR(body->value(Vec3(1, 0, 0)), -2.0, 1e-12);
    EXPECT_NEAR(body->value(Vec3(3, 0, 0)), 0.0, 1e-12);
    EXPECT_NEAR(body->value(Vec3(1, 5, 0)), 3.0, 1e-12);
}

TEST(MakeBody, CsgDifferenceCarvesTheHole) {
    const Case c = parse_case(R"({"geometry": {"difference": [
        {"box": {"size": [2, 2, 2]}}, {"cylinder": {"radius": 0.5, "height": 4}}]}})", "c.json");
    const Body body = make_body(c.geometry);
    EXPECT_GT(body->value(Vec3(0, 0, 0)), 0.0);       // in the hole
    EXPECT_LT(body->value(Vec3(0.75, 0.75, 0)), 0.0);  // in the material
    EXPECT_NEAR(body->value(Vec3(0.5, 0, 0)), 0.0, 1e-12);
}

TEST(MakeBody, EveryPrimitiveIsNegativeAtItsCentre) {
    for (const char* g : {R"({"sphere": {"radius": 1}})", R"({"ellipsoid": {"semi_axes": [3, 2, 1]}})",
                          R"({"box": {"size": [1, 2, 3]}})", R"({"cylinder": {"radius": 1, "height": 2}})",
                          R"({"cone": {"bottom_radius": 1, "top_radius": 0.2, "height": 2}})"}) {
        const Case c = parse_case(std::string(R"({"geometry": )") + g + "}", "c.json");
        EXPECT_LT(make_body(c.geometry)->value(Vec3(0, 0, 0)), 0.0) << g;
    }
}

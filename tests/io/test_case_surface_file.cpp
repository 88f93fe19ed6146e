// Case files: a body given as a surface file ({"file": ..., "voxel_size": ...}).
#include <gtest/gtest.h>

#include "io/case_file.h"

namespace hexmesh {
namespace {

std::string error_of(const std::string& text) {
    try {
        parse_case(text, "cases/x/case.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(CaseSurfaceFile, PathIsRelativeToTheCaseFolder) {
    const Case c = parse_case(R"({"geometry": {"file": "../parts/wing.stl", "voxel_size": 0.5}})",
                              "cases/x/case.json");
    EXPECT_EQ(c.geometry.kind, BodyKind::file);
    EXPECT_EQ(c.geometry.file, "cases/parts/wing.stl");
    EXPECT_EQ(c.geometry.voxel_size, 0.5);
    const Case absolute = parse_case(R"({"geometry": {"file": "/data/a.obj"}})", "case.json");
    EXPECT_EQ(absolute.geometry.file, "/data/a.obj");
    EXPECT_EQ(absolute.geometry.voxel_size, 0);
}

TEST(CaseSurfaceFile, UsableInsideCsgWithTransforms) {
    const Case c = parse_case(
        R"({"geometry": {"difference": [{"file": "a.stl", "scale": 2}, {"sphere": {"radius": 1}}]}})",
        "dir/case.json");
    ASSERT_EQ(c.geometry.children.size(), 2u);
    EXPECT_EQ(c.geometry.children[0].file, "dir/a.stl");
    EXPECT_EQ(c.geometry.children[0].scale, 2);
}

TEST(CaseSurfaceFile, FeatureAngleGoesWithTheFile) {
    const Case c =
        parse_case(R"({"geometry": {"file": "part.stl", "feature_angle": 45}})", "/d/c.json");
    EXPECT_EQ(c.geometry.feature_angle, 45);
    EXPECT_EQ(parse_case(case_to_json(c), "g.json").geometry.feature_angle, 45);
    EXPECT_EQ(parse_case(R"({"geometry": {"file": "part.stl"}})", "c.json").geometry.feature_angle,
              30);
    EXPECT_NE(error_of(R"({"geometry": {"file": "part.stl", "feature_angle": 0}})")
                  .find("geometry.feature_angle: expected an angle in (0, 180] degrees"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}, "feature_angle": 30}})")
                  .find("geometry.feature_angle: expected no feature angle: it goes with \"file\""),
              std::string::npos);
}

TEST(CaseSurfaceFile, BadValuesNameTheKey) {
    EXPECT_NE(error_of(R"({"geometry": {"file": 3}})")
                  .find("geometry.file: expected a surface file name"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"file": "a.stl", "voxel_size": -1}})")
                  .find("geometry.voxel_size: expected a positive number"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}, "voxel_size": 1}})")
                  .find("geometry.voxel_size: expected no voxel size"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"file": "a.stl", "sphere": {"radius": 1}}})")
                  .find("expected exactly one shape"),
              std::string::npos);
}

}  // namespace
}  // namespace hexmesh

#include <gtest/gtest.h>

#include <string>

#include "io/case_file.h"

using namespace hexmesh;

namespace {

// The message of the InputError `text` raises, or "" if it parses.
std::string error_of(const std::string& text) {
    try {
        parse_case(text, "case.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(CaseFile, ParsesAFullCase) {
    const Case c = parse_case(R"({
      "geometry": {"sphere": {"center": [1, 2, 3], "radius": 0.5}, "scale": 2},
      "grid": {"topology": "o-h", "cells_per_edge": 16, "wall_cells": 8, "core_size": 0.4},
      "boundary_layer": {"first_height": 0.001, "growth_ratio": 1.1, "layers": 5},
      "solver": {"method": "lbfgs", "theta": 0.7, "max_iterations": 50},
      "outputs": ["vtk"]
    })", "case.json");
    EXPECT_EQ(c.geometry.kind, "sphere");
    EXPECT_EQ(c.geometry.center, Vec3(1, 2, 3));
    EXPECT_DOUBLE_EQ(c.geometry.radius, 0.5);
    EXPECT_DOUBLE_EQ(c.geometry.scale, 2);
    EXPECT_EQ(c.grid.cells_per_edge, 16);
    EXPECT_EQ(c.grid.wall_cells, 8);
    EXPECT_DOUBLE_EQ(c.grid.core_size, 0.4);
    ASSERT_TRUE(c.boundary_layer);
    EXPECT_EQ(c.boundary_layer->layers, 5);
    EXPECT_EQ(c.solver.method, "lbfgs");
    EXPECT_EQ(c.outputs, std::vector<std::string>{"vtk"});
}

TEST(CaseFile, ParsesCsgWithTransforms) {
    const Case c = parse_case(R"({"geometry": {"difference": [
        {"box": {"size": [2, 2, 2]}},
        {"cylinder": {"radius": 0.5, "height": 3}, "rotate": {"axis": [1, 0, 0], "degrees": 90}}
      ]}})", "case.json");
    ASSERT_EQ(c.geometry.kind, "difference");
    ASSERT_EQ(c.geometry.children.size(), 2u);
    EXPECT_EQ(c.geometry.children[1].kind, "cylinder");
    EXPECT_DOUBLE_EQ(c.geometry.children[1].rotate_degrees, 90);
}

TEST(CaseFile, MalformedJsonNamesTheLine) {
    const std::string e = error_of("{\n  \"geometry\": {\"sphere\": {\"radius\": 1}},\n  \"grid\": {,}\n}");
    EXPECT_NE(e.find("case.json: malformed JSON"), std::string::npos) << e;
    EXPECT_NE(e.find("line 3"), std::string::npos) << e;
}

TEST(CaseFile, UnknownKeyIsNamedWithItsPath) {
    const std::string e =
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cels_per_edge": 10}})");
    EXPECT_NE(e.find("grid.cels_per_edge: unknown key"), std::string::npos) << e;
    EXPECT_NE(e.find("cells_per_edge"), std::string::npos) << e;  // the allowed keys are listed
}

TEST(CaseFile, WrongTypeNamesKeyAndExpectedType) {
    const std::string e =
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": "ten"}})");
    EXPECT_NE(e.find("grid.cells_per_edge: expected an integer in [2, 4096], got string"),
              std::string::npos)
        << e;
}

TEST(CaseFile, NegativeSizesAreRefused) {
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": -1}}})")
                  .find("geometry.sphere.radius: expected a positive number, got number -1"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"box": {"size": [1, -2, 1]}}})")
                  .find("geometry.box.size: expected an array of 3 positive numbers"),
              std::string::npos);
}

TEST(CaseFile, AbsurdSizesAreRefused) {
    const std::string e = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": 4000, "wall_cells": 4000}})");
    EXPECT_NE(e.find("grid.cells_per_edge: expected a grid of at most"), std::string::npos) << e;
}

TEST(CaseFile, NanIsNotAcceptedAsANumber) {
    // JSON has no NaN literal; the parser rejects it as malformed.
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": NaN}}})").find("malformed JSON"),
              std::string::npos);
}

TEST(CaseFile, GeometryNeedsExactlyOneShape) {
    EXPECT_NE(error_of(R"({"grid": {}})").find("geometry: expected an object describing the body"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}, "box": {"size": [1, 1, 1]}}})")
                  .find("expected exactly one shape"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"union": [{"sphere": {"radius": 1}}]}})")
                  .find("geometry.union: expected an array of at least 2 shapes"),
              std::string::npos);
}

TEST(CaseFile, BoundaryLayerMustFitTheWallBlock) {
    const std::string e = error_of(R"({"geometry": {"sphere": {"radius": 1}},
        "grid": {"wall_cells": 6}, "boundary_layer": {"first_height": 0.01, "layers": 6}})");
    EXPECT_NE(e.find("boundary_layer.layers: expected an integer in [1, 5]"), std::string::npos)
        << e;
}

TEST(CaseFile, UnknownOutputFormatIsRefused) {
    const std::string e =
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "outputs": ["vtk", "fluent"]})");
    EXPECT_NE(e.find("outputs[1]: expected a format name (vtk), got string \"fluent\""),
              std::string::npos)
        << e;
}

TEST(CaseFile, MissingFileIsNamed) {
    try {
        read_case("/nonexistent/case.json");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/case.json: cannot open case file"),
                  std::string::npos);
    }
}

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
      "solver": {"untangle": "lbfgs", "optimize": "explicit", "theta": 0.7, "max_iterations": 50,
                 "surface_iterations": 0, "wall_fidelity": 3.5},
      "outputs": ["vtk"]
    })",
                              "case.json");
    EXPECT_EQ(c.geometry.kind, BodyKind::sphere);
    EXPECT_EQ(c.geometry.center, Vec3(1, 2, 3));
    EXPECT_DOUBLE_EQ(c.geometry.radius, 0.5);
    EXPECT_DOUBLE_EQ(c.geometry.scale, 2);
    EXPECT_EQ(c.grid.cells_per_edge, 16);
    EXPECT_EQ(c.grid.wall_cells, 8);
    EXPECT_DOUBLE_EQ(c.grid.core_size, 0.4);
    ASSERT_TRUE(c.boundary_layer);
    EXPECT_EQ(c.boundary_layer->layers, 5);
    EXPECT_EQ(c.solver.untangle, "lbfgs");
    EXPECT_EQ(c.solver.optimize, "explicit");
    EXPECT_EQ(c.solver.surface_iterations, 0);
    EXPECT_DOUBLE_EQ(c.solver.wall_fidelity, 3.5);
    EXPECT_EQ(c.domain, Domain::interior);
    EXPECT_EQ(c.outputs, std::vector<std::string>{"vtk"});
}

TEST(CaseFile, ParsesCsgWithTransforms) {
    const Case c = parse_case(R"({"geometry": {"difference": [
        {"box": {"size": [2, 2, 2]}},
        {"cylinder": {"radius": 0.5, "height": 3}, "rotate": {"axis": [1, 0, 0], "degrees": 90}}
      ]}})",
                              "case.json");
    ASSERT_EQ(c.geometry.kind, BodyKind::csg_difference);
    ASSERT_EQ(c.geometry.children.size(), 2u);
    EXPECT_EQ(c.geometry.children[1].kind, BodyKind::cylinder);
    EXPECT_DOUBLE_EQ(c.geometry.children[1].rotate_degrees, 90);
}

TEST(CaseFile, MalformedJsonNamesTheLine) {
    const std::string e =
        error_of("{\n  \"geometry\": {\"sphere\": {\"radius\": 1}},\n  \"grid\": {,}\n}");
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

// run optimizes shape first by default (README, "solver"); a case may set it in (0, 1).
TEST(CaseFile, ThetaDefaultsToShapeFirstAndStaysInsideZeroOne) {
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "case.json").solver.theta,
              0.2);
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}, "solver": {"theta": 0.8}})",
                         "case.json")
                  .solver.theta,
              0.8);
    const std::string e =
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "solver": {"theta": 1.5}})");
    EXPECT_NE(e.find("solver.theta"), std::string::npos) << e;
}

TEST(CaseFile, SurfaceIterationsAreACountThatDefaultsToTen) {
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "case.json")
                  .solver.surface_iterations,
              10);
    const std::string e = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "solver": {"surface_iterations": -1}})");
    EXPECT_NE(e.find("solver.surface_iterations"), std::string::npos) << e;
}

TEST(CaseFile, WallFidelityIsAWeightThatDefaultsToZero) {
    EXPECT_EQ(
        parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "case.json").solver.wall_fidelity,
        0);
    for (const char* bad : {"-1", "1e7", "\"high\""}) {
        const std::string e = error_of(
            std::string(R"({"geometry": {"sphere": {"radius": 1}}, "solver": {"wall_fidelity": )") +
            bad + "}}");
        EXPECT_NE(e.find("solver.wall_fidelity"), std::string::npos) << e;
    }
}

TEST(CaseFile, AbsurdSizesAreRefused) {
    const std::string e = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": 4000, "wall_cells": 4000}})");
    EXPECT_NE(e.find("grid.cells_per_edge: expected a grid of at most"), std::string::npos) << e;
    // Outside, the lines' default count (twice cells_per_edge) is counted too: 300 per edge
    // is 27 M cells inside the wall but 324 M outside.
    const std::string outside = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior", "grid": {"cells_per_edge": 300}})");
    EXPECT_NE(outside.find("(this one has 351000000)"), std::string::npos) << outside;
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
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "outputs": ["vtk", "tecplot"]})");
    EXPECT_NE(e.find("outputs[1]: expected a format name (vtk), got string \"tecplot\""),
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

TEST(CaseFile, ExteriorDomainWithFarField) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior",
      "far_field": {"shape": "box", "size": 12}, "grid": {"cell_size": 0.1, "wall_cells": 30}})",
                              "case.json");
    EXPECT_EQ(c.domain, Domain::exterior);
    EXPECT_EQ(c.far_field.shape, FarFieldShape::box);
    EXPECT_DOUBLE_EQ(c.far_field.size, 12);
    EXPECT_DOUBLE_EQ(c.grid.cell_size, 0.1);
    EXPECT_EQ(c.grid.wall_cells, 30);
    // Not given: twice the patch's cells out to the far field, and 10 from a core to the wall.
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior",
                            "grid": {"cells_per_edge": 12}})",
                         "c.json")
                  .grid.wall_cells,
              24);
    EXPECT_EQ(
        parse_case(R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior"})", "c.json")
            .grid.wall_cells,
        40);
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "c.json").grid.wall_cells,
              10);
}

TEST(CaseFile, FarFieldNeedsAnExteriorDomain) {
    const std::string e =
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "far_field": {"size": 10}})");
    EXPECT_NE(e.find("far_field"), std::string::npos) << e;
    EXPECT_NE(e.find("\"domain\": \"exterior\""), std::string::npos) << e;
    EXPECT_NE(
        error_of(R"({"geometry": {"sphere": {"radius": 1}}, "domain": "outside"})").find("domain"),
        std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior",
                           "grid": {"topology": "single-block"}})")
                  .find("grid.topology"),
              std::string::npos);
}

TEST(CaseFile, CellSizeAndCellsPerEdgeExcludeEachOther) {
    const std::string e = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": 8, "cell_size": 0.1}})");
    EXPECT_NE(e.find("grid.cell_size"), std::string::npos) << e;
}

// White's flat-plate estimate, worked by hand: air (rho 1.225, mu 1.789e-5) at 10 m/s over
// 1 m: Re = 684 740, Cf = 0.026 / Re^(1/7) = 3.813e-3, u_tau = 0.4367 m/s, y(y+ = 1) = 3.344e-5 m.
TEST(CaseFile, FirstHeightFromYPlus) {
    EXPECT_NEAR(first_height_from_y_plus(1, 684740, 10, 1.225, 1.789e-5), 3.344e-5, 0.005e-5);
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}},
      "boundary_layer": {"y_plus": 1, "velocity": 10, "density": 1.225, "viscosity": 1.789e-5,
                         "length": 1, "growth_ratio": 1.2, "layers": 5}})",
                              "case.json");
    ASSERT_TRUE(c.boundary_layer);
    EXPECT_NEAR(c.boundary_layer->reynolds, 684740, 1);
    EXPECT_NEAR(c.boundary_layer->first_height, 3.344e-5, 0.005e-5);
    const std::string both = error_of(R"({"geometry": {"sphere": {"radius": 1}},
      "boundary_layer": {"y_plus": 1, "first_height": 0.01, "layers": 3}})");
    EXPECT_NE(both.find("either first_height or y_plus"), std::string::npos) << both;
    const std::string missing = error_of(R"({"geometry": {"sphere": {"radius": 1}},
      "boundary_layer": {"y_plus": 1, "velocity": 10, "density": 1.2, "viscosity": 1e-5, "layers": 3}})");
    EXPECT_NE(missing.find("boundary_layer.length"), std::string::npos) << missing;
}

TEST(CaseFile, RefinementLevels) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}},
                                  "refinement": {"levels": 3}})",
                              "case.json");
    EXPECT_EQ(c.refinement.levels, 3);
    EXPECT_EQ(parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "c.json").refinement.levels,
              1);
}

TEST(CaseFile, RefinementLevelsOutOfRangeOrUnknownKeysAreRefused) {
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}}, "refinement": {"levels": 6}})")
                  .find("refinement.levels"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}}, "refinement": {"levels": 0}})")
                  .find("refinement.levels"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}}, "refinement": {"ratio": 2}})")
                  .find("refinement.ratio"),
              std::string::npos);
}

TEST(CaseFile, CaseToJsonReadsBackTheSameGridAndGeometry) {
    const Case c = parse_case(R"({
      "geometry": {"difference": [{"box": {"size": [2, 2, 2]}},
                                  {"cylinder": {"radius": 0.5, "height": 3}}],
                   "rotate": {"axis": [0, 0, 1], "degrees": 30}, "translate": [1, 0, 0]},
      "grid": {"cells_per_edge": 12, "wall_cells": 5, "core_size": 0.4},
      "boundary_layer": {"y_plus": 1, "velocity": 10, "density": 1.2, "viscosity": 1.8e-5,
                         "length": 1, "layers": 3},
      "solver": {"optimize": "lbfgs", "optimize_iterations": 4},
      "refinement": {"levels": 2}
    })",
                              "case.json");
    const Case back = parse_case(case_to_json(c), "grid.case.json");
    EXPECT_EQ(back.geometry.kind, BodyKind::csg_difference);
    ASSERT_EQ(back.geometry.children.size(), 2u);
    EXPECT_EQ(back.geometry.children[1].radius, 0.5);
    EXPECT_EQ(back.geometry.rotate_degrees, 30);
    EXPECT_EQ(back.geometry.translate, Vec3(1, 0, 0));
    EXPECT_EQ(back.grid.cells_per_edge, 12);
    EXPECT_EQ(back.grid.wall_cells, 5);
    ASSERT_TRUE(back.boundary_layer);
    EXPECT_DOUBLE_EQ(back.boundary_layer->first_height, c.boundary_layer->first_height);
    EXPECT_EQ(back.solver.optimize, "lbfgs");
    EXPECT_EQ(back.refinement.levels, 1);  // a run setting, not part of the grid
}

TEST(CaseFile, GridAxisIsAutoByDefaultAndReadsBack) {
    const char* sphere = R"({"geometry": {"sphere": {"radius": 1}}})";
    EXPECT_EQ(parse_case(sphere, "case.json").grid.axis, GridAxis::automatic);
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}},
      "grid": {"cells_per_edge": 12, "axis": "y", "ring_cells": 5, "frame_cells": 2}})",
                              "case.json");
    EXPECT_EQ(c.grid.axis, GridAxis::y);
    EXPECT_EQ(c.grid.ring_cells, 5);
    EXPECT_EQ(c.grid.frame_cells, 2);
    const Case back = parse_case(case_to_json(c), "grid.case.json");
    EXPECT_EQ(back.grid.axis, GridAxis::y);
    EXPECT_EQ(back.grid.ring_cells, 5);
    EXPECT_EQ(back.grid.frame_cells, 2);
}

TEST(CaseFile, GridAxisMisusesAreNamed) {
    EXPECT_NE(error_of(R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"axis": "w"}})")
                  .find("grid.axis"),
              std::string::npos);
    const std::string rings = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"axis": "none", "ring_cells": 4}})");
    EXPECT_NE(rings.find("grid.ring_cells"), std::string::npos) << rings;
    const std::string frame = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": 8, "frame_cells": 4}})");
    EXPECT_NE(frame.find("grid.frame_cells"), std::string::npos) << frame;
    const std::string single = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"topology": "single-block", "axis": "z"}})");
    EXPECT_NE(single.find("grid.axis"), std::string::npos) << single;
    const std::string outside = error_of(
        R"({"geometry": {"sphere": {"radius": 1}}, "domain": "exterior", "grid": {"axis": "z"}})");
    EXPECT_NE(outside.find("grid.axis"), std::string::npos) << outside;
    // "auto" goes with any topology and domain: it picks an axis only for an O-H interior.
    EXPECT_NO_THROW(parse_case(
        R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"topology": "single-block", "axis": "auto"}})",
        "case.json"));
}

TEST(CaseFile, AnAxisResolvedToNoneReadsBackWithoutItsRingSizes) {
    // "auto" with ring sizes, on a body where it finds no axis: the case written with the
    // grid says "none" and reads back (hexmesh refine reads it).
    Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}},
      "grid": {"cells_per_edge": 12, "ring_cells": 5, "frame_cells": 2}})",
                        "case.json");
    c.grid.axis = GridAxis::none;
    const Case back = parse_case(case_to_json(c), "grid.case.json");
    EXPECT_EQ(back.grid.axis, GridAxis::none);
}

TEST(CaseFile, TheCoarsestGridNeedsNoFrame) {
    // 2 cells per edge leave no room for an axial core's frame; "auto" then keeps one block.
    EXPECT_EQ(
        parse_case(R"({"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": 2}})",
                   "case.json")
            .grid.cells_per_edge,
        2);
}

TEST(CaseFile, FlowDefaultsToLaminarReynolds100AndReadsBack) {
    const Case d = parse_case(R"({"geometry": {"sphere": {"radius": 1}}})", "case.json");
    EXPECT_EQ(d.flow.velocity, Vec3(1, 0, 0));
    EXPECT_EQ(d.flow.density, 1);
    EXPECT_EQ(d.flow.viscosity, 0.01);
    EXPECT_EQ(d.flow.turbulence, "laminar");
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}},
      "flow": {"velocity": [0, 30, 0], "density": 1.2, "viscosity": 1.8e-5,
               "turbulence": "k-omega-sst", "turbulence_intensity": 0.02, "turbulence_length": 0.05}})",
                              "case.json");
    const Case back = parse_case(case_to_json(c), "grid.case.json");
    EXPECT_EQ(back.flow.velocity, Vec3(0, 30, 0));
    EXPECT_EQ(back.flow.density, 1.2);
    EXPECT_EQ(back.flow.viscosity, 1.8e-5);
    EXPECT_EQ(back.flow.turbulence, "k-omega-sst");
    EXPECT_EQ(back.flow.turbulence_intensity, 0.02);
    EXPECT_EQ(back.flow.turbulence_length, 0.05);
}

TEST(CaseFile, FlowMisusesAreNamed) {
    const std::string sphere = R"({"geometry": {"sphere": {"radius": 1}}, "flow": )";
    const std::vector<std::pair<std::string, std::string>> bad = {
        {R"({"velocity": [0, 0, 0]})", "flow.velocity: expected a non-zero vector"},
        {R"({"viscosity": -1})", "flow.viscosity"},
        {R"({"turbulence": "k-epsilon"})", "flow.turbulence"},
        {R"({"speed": 3})", "flow.speed"},
    };
    for (const auto& [flow, message] : bad) {
        const std::string e = error_of(sphere + flow + "}");
        EXPECT_NE(e.find(message), std::string::npos) << flow << ": " << e;
    }
}

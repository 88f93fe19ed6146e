#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hexmesh/pipeline/make_body.h"

using namespace hexmesh;

TEST(MakeBody, TransformedSphereIsTheMovedSphere) {
    const Case c = parse_case(R"({"geometry": {"sphere": {"radius": 1}, "scale": 2,
        "translate": [1, 0, 0], "rotate": {"axis": [0, 0, 1], "degrees": 90}}})",
                              "c.json");
    const Body body = make_body(c.geometry);
    EXPECT_NEAR(body->value(Vec3(1, 0, 0)), -2.0, 1e-12);
    EXPECT_NEAR(body->value(Vec3(3, 0, 0)), 0.0, 1e-12);
    EXPECT_NEAR(body->value(Vec3(1, 5, 0)), 3.0, 1e-12);
}

TEST(MakeBody, CsgDifferenceCarvesTheHole) {
    const Case c = parse_case(R"({"geometry": {"difference": [
        {"box": {"size": [2, 2, 2]}}, {"cylinder": {"radius": 0.5, "height": 4}}]}})",
                              "c.json");
    const Body body = make_body(c.geometry);
    EXPECT_GT(body->value(Vec3(0, 0, 0)), 0.0);        // in the hole
    EXPECT_LT(body->value(Vec3(0.75, 0.75, 0)), 0.0);  // in the material
    EXPECT_NEAR(body->value(Vec3(0.5, 0, 0)), 0.0, 1e-12);
}

TEST(MakeBody, EveryPrimitiveIsNegativeAtItsCentre) {
    for (const char* g :
         {R"({"sphere": {"radius": 1}})", R"({"ellipsoid": {"semi_axes": [3, 2, 1]}})",
          R"({"box": {"size": [1, 2, 3]}})", R"({"cylinder": {"radius": 1, "height": 2}})",
          R"({"cone": {"bottom_radius": 1, "top_radius": 0.2, "height": 2}})"}) {
        const Case c = parse_case(std::string(R"({"geometry": )") + g + "}", "c.json");
        EXPECT_LT(make_body(c.geometry)->value(Vec3(0, 0, 0)), 0.0) << g;
    }
}

// A closed surface whose triangles all face inwards (as marching cubes on a distance field
// writes them) is turned over: the sphere map would otherwise place the wall mirrored, and
// the grid built on it inside out.
TEST(MakeBody, ASurfaceFacingInwardsIsTurnedOver) {
    // A tetrahedron, each triangle counter-clockwise seen from inside.
    const std::string path =
        (std::filesystem::temp_directory_path() / "hexmesh_inward_tet.stl").string();
    {
        std::ofstream out(path);
        const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // inward
        out << "solid t\n";
        for (const auto& f : faces) {
            out << "facet normal 0 0 0\nouter loop\n";
            for (int v : f) out << "vertex " << p[v][0] << " " << p[v][1] << " " << p[v][2] << "\n";
            out << "endloop\nendfacet\n";
        }
        out << "endsolid t\n";
    }
    GeometrySpec spec;
    spec.kind = BodyKind::file;
    spec.file = path;
    const std::optional<TriangleSurface> s = reference_surface(spec);
    ASSERT_TRUE(s);
    EXPECT_NEAR(signed_volume(*s), 1.0 / 6, 1e-12);
    TriangleSurface inward = *s;
    turn_over(inward);
    EXPECT_NEAR(signed_volume(inward), -1.0 / 6, 1e-12);
    std::filesystem::remove(path);
}

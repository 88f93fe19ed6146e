// `hexmesh run` on bodies from surface files: what the block structure cannot grid is refused
// at once, and the report measures how closely the grid's wall follows the surface.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "tests/surface/sample_surfaces.h"

using namespace hexmesh;
using namespace hexmesh::test_support;
namespace fs = std::filesystem;

namespace {

const fs::path bodies = fs::path(HEXMESH_SOURCE_DIR) / ".." / "shared" / "data" / "bodies";

struct Refusal {
    CommandResult result;
    bool wrote = false;
};

// `hexmesh run` of a case naming only the file and the domain.
Refusal run_file(const fs::path& surface, const std::string& domain) {
    const fs::path dir = scratch("bodies_" + surface.stem().string() + "_" + domain);
    fs::create_directories(dir);
    std::ofstream(dir / "case.json") << nlohmann::json{{"geometry", {{"file", surface.string()}}},
                                                       {"domain", domain}}
                                            .dump();
    Refusal r;
    r.result = run_hexmesh("run '" + (dir / "case.json").string() + "' -o '" + (dir / "out").string() + "'");
    r.wrote = fs::exists(dir / "out");
    return r;
}

void expect_refused_at_once(const Refusal& r, const std::string& message) {
    EXPECT_EQ(r.result.exit_code, 1) << r.result.out << r.result.err;
    EXPECT_EQ(count_lines(r.result.err), 1) << r.result.err;
    EXPECT_NE(r.result.err.find(message), std::string::npos) << r.result.err;
    // Before any grid work: the body's distance field (the "geometry" phase) is never built.
    EXPECT_EQ(r.result.out.find("\n  geometry"), std::string::npos) << r.result.out;
    EXPECT_FALSE(r.wrote);
}

}  // namespace

TEST(CliBodies, ASurfaceWithAHandleIsRefusedAtOnce) {
    const fs::path file = scratch("torus.stl");
    test::write_stl_binary(file.string(), test::torus_surface(1, 0.3, 48, 24));
    for (const char* domain : {"interior", "exterior"})
        expect_refused_at_once(run_file(file, domain),
                            "genus 1: the surface has 1 handle (V - E + F = 0); hexmesh grids bodies "
                            "without holes through them");
}

TEST(CliBodies, TwoSolidsInOneFileAreRefusedAtOnce) {
    TriangleSurface two = test::uv_sphere(Vec3::Zero(), 1, 24, 12);
    const TriangleSurface box = test::box_surface(Vec3(2, 2, 2), Vec3(3, 3, 3), 2);
    const int offset = int(two.points.size());
    two.points.insert(two.points.end(), box.points.begin(), box.points.end());
    for (auto t : box.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    const fs::path file = scratch("two.stl");
    test::write_stl_ascii(file.string(), two);
    expect_refused_at_once(run_file(file, "exterior"),
                        "2 separate bodies (the largest has 528 triangles, the next 48): hexmesh "
                        "grids one closed body");
}

TEST(CliBodies, TheSharedBodiesWithHandlesOrTwoSolidsAreRefusedAtOnce) {
    if (!fs::exists(bodies)) GTEST_SKIP() << "shared bodies not beside the project: " << bodies;
    expect_refused_at_once(run_file(bodies / "knot.off", "exterior"), "genus 1: the surface has 1 handle");
    expect_refused_at_once(run_file(bodies / "rotor.off", "interior"), "genus 1: the surface has 1 handle");
    expect_refused_at_once(run_file(bodies / "simpleCar.stl", "exterior"), "2 separate bodies");
}

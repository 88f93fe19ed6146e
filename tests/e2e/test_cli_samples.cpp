// End-to-end: bodies from a point cloud and from a stack of cross-sections (hexmesh run).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

#include "cli.h"

using namespace hexmesh::test_support;
namespace fs = std::filesystem;

namespace {

// n points of the unit sphere (Fibonacci lattice) with outward normals, as XYZ text; every
// point i with i % flip_every == 1 gets an inward normal instead (flip_every 0: none).
void write_sphere_xyz(const fs::path& file, int n, int flip_every = 0) {
    std::ofstream out(file);
    out << std::setprecision(17) << "# unit sphere, x y z nx ny nz\n";
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
        const double x = r * std::cos(golden * i), y = r * std::sin(golden * i);
        const double s = flip_every > 0 && i % flip_every == 1 ? -1 : 1;
        out << x << ' ' << y << ' ' << z << ' ' << s * x << ' ' << s * y << ' ' << s * z << '\n';
    }
}

// A stack of circles of radius 1 at z = 0, 0.5, 1.5 (64 points each), plus `extra` lines.
void write_circle_stack(const fs::path& file, const std::string& extra) {
    std::ofstream out(file);
    out << std::setprecision(17);
    for (double z : {0.0, 0.5, 1.5}) {
        out << "slice " << z << '\n';
        for (int i = 0; i < 64; ++i)
            out << std::cos(2 * M_PI * i / 64) << ' ' << std::sin(2 * M_PI * i / 64) << '\n';
    }
    out << extra;
}

CommandResult run_case(const fs::path& dir, const std::string& geometry) {
    std::ofstream(dir / "case.json") << "{\"geometry\": " << geometry
                                     << ", \"grid\": {\"cells_per_edge\": 8, \"wall_cells\": 4}}";
    return run_hexmesh("run '" + (dir / "case.json").string() + "' -o '" + (dir / "out").string() +
                       "'");
}

}  // namespace

TEST(CliSamples, SpherePointCloudGivesAValidGrid) {
    const fs::path dir = scratch("points");
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_sphere_xyz(dir / "sphere.xyz", 3000);
    const CommandResult r = run_case(dir, R"({"points": "sphere.xyz"})");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(row_value(r.out, "inverted corner tets"), 0) << r.out;
    EXPECT_TRUE(fs::exists(dir / "out" / "grid.vtm"));
    fs::remove_all(dir);
}

TEST(CliSamples, PointCloudTakesTransformsInsideCsg) {
    const fs::path dir = scratch("points_csg");
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_sphere_xyz(dir / "sphere.xyz", 3000);
    const CommandResult plain = run_case(dir, R"({"points": "sphere.xyz"})");
    const CommandResult scaled =
        run_case(dir, R"({"union": [{"points": "sphere.xyz", "scale": 2, "translate": [1, 0, 0]},
                           {"sphere": {"center": [1, 0, 0], "radius": 0.5}}]})");
    EXPECT_EQ(scaled.exit_code, 0) << scaled.out << scaled.err;
    EXPECT_EQ(row_value(scaled.out, "inverted corner tets"), 0) << scaled.out;
    // The wall edge doubles with the body.
    EXPECT_NEAR(real_value(scaled.out, "h (mean wall edge)"),
                2 * real_value(plain.out, "h (mean wall edge)"), 0.01)
        << plain.out << scaled.out;
    fs::remove_all(dir);
}

TEST(CliSamples, CrossSectionStackGivesAValidGrid) {
    // A sphere of radius 1 cut at |z| = 0.9: circles at 19 levels, 128 points each.
    const fs::path dir = scratch("sections");
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        std::ofstream out(dir / "stack.txt");
        out << std::setprecision(17);
        for (int k = 0; k <= 18; ++k) {
            const double z = -0.9 + 0.1 * k, radius = std::sqrt(1 - z * z);
            out << "slice " << z << '\n';
            for (int i = 0; i < 128; ++i)
                out << radius * std::cos(2 * M_PI * i / 128) << ' '
                    << radius * std::sin(2 * M_PI * i / 128) << '\n';
        }
    }
    const CommandResult r = run_case(dir, R"({"sections": "stack.txt"})");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(row_value(r.out, "inverted corner tets"), 0) << r.out;
    fs::remove_all(dir);
}

TEST(CliSamples, InspectReportsPointClouds) {
    const fs::path dir = scratch("inspect_points");
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_sphere_xyz(dir / "clean.xyz", 3000);
    write_sphere_xyz(dir / "flipped.xyz", 3000, 600);  // points 1, 601, ..., 2401
    const CommandResult clean = run_hexmesh("inspect '" + (dir / "clean.xyz").string() + "'");
    ASSERT_EQ(clean.exit_code, 0) << clean.err;
    EXPECT_NE(clean.out.find("point cloud "), std::string::npos) << clean.out;
    EXPECT_EQ(row_value(clean.out, "points (with normals)"), 3000) << clean.out;
    EXPECT_EQ(row_value(clean.out, "duplicate points"), 0) << clean.out;
    EXPECT_EQ(row_value(clean.out, "normals against neighbours"), 0) << clean.out;
    // 3000 points on an area of 4 pi: about sqrt(4 pi / 3000) = 0.065 apart.
    EXPECT_GT(real_value(clean.out, "mean spacing"), 0.04) << clean.out;
    EXPECT_LT(real_value(clean.out, "mean spacing"), 0.07) << clean.out;
    EXPECT_NE(clean.out.find("consistent: yes"), std::string::npos) << clean.out;
    const CommandResult flipped = run_hexmesh("inspect '" + (dir / "flipped.xyz").string() + "'");
    EXPECT_EQ(row_value(flipped.out, "normals against neighbours"), 5) << flipped.out;
    EXPECT_NE(flipped.out.find("consistent: no"), std::string::npos) << flipped.out;

    // A PLY with vertices and normals but no faces is a point cloud too.
    {
        std::ofstream ply(dir / "cloud.ply");
        ply << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
               "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
               "end_header\n1 0 0 1 0 0\n-1 0 0 -1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n";
    }
    const CommandResult ply = run_hexmesh("inspect '" + (dir / "cloud.ply").string() + "'");
    EXPECT_EQ(ply.exit_code, 0) << ply.err;
    EXPECT_EQ(row_value(ply.out, "points (with normals)"), 4) << ply.out;
    fs::remove_all(dir);
}

TEST(CliSamples, InspectReportsCrossSectionStacks) {
    const fs::path dir = scratch("inspect_sections");
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_circle_stack(dir / "stack.txt", "");
    const CommandResult good = run_hexmesh("inspect '" + (dir / "stack.txt").string() + "'");
    ASSERT_EQ(good.exit_code, 0) << good.err;
    EXPECT_NE(good.out.find("cross-section stack "), std::string::npos) << good.out;
    EXPECT_EQ(row_value(good.out, "sections"), 3) << good.out;
    EXPECT_EQ(row_value(good.out, "polylines"), 3) << good.out;
    EXPECT_EQ(row_value(good.out, "points"), 192) << good.out;
    EXPECT_NE(good.out.find("0.5 1"), std::string::npos) << good.out;  // spacing min/max
    // The 64-gon's area: 32 sin(2 pi / 64).
    EXPECT_NEAR(real_value(good.out, "smallest polyline area"), 32 * std::sin(2 * M_PI / 64), 1e-5);
    EXPECT_EQ(row_value(good.out, "self-intersecting polylines"), 0) << good.out;
    EXPECT_EQ(row_value(good.out, "crossing polyline pairs"), 0) << good.out;
    EXPECT_NE(good.out.find("valid: yes"), std::string::npos) << good.out;

    // A fourth section: a bow tie (crossing itself) and a square that cuts the circle there.
    write_circle_stack(dir / "bad.sec",
                       "slice 2\n0 0\n0.4 0.4\n0.4 0\n0 0.4\n"
                       "loop\n0.9 -0.1\n1.2 -0.1\n1.2 0.1\n0.9 0.1\n"
                       "loop\n0 -1\n1 0\n0 1\n-1 0\n");
    const CommandResult bad = run_hexmesh("inspect '" + (dir / "bad.sec").string() + "'");
    ASSERT_EQ(bad.exit_code, 0) << bad.err;
    EXPECT_EQ(row_value(bad.out, "self-intersecting polylines"), 1) << bad.out;
    EXPECT_EQ(row_value(bad.out, "crossing polyline pairs"), 1) << bad.out;
    EXPECT_NE(bad.out.find("valid: no"), std::string::npos) << bad.out;
    // --as overrides the guess from the name.
    const CommandResult as_surface =
        run_hexmesh("inspect '" + (dir / "stack.txt").string() + "' --as surface");
    EXPECT_NE(as_surface.exit_code, 0);
    fs::remove_all(dir);
}

TEST(CliSamples, BadPointCloudIsOneErrorLine) {
    const fs::path dir = scratch("bad_points");
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "cloud.xyz") << "0 0 0 1 0 0\n1 1 1\n";
    const CommandResult r = run_case(dir, R"({"points": "cloud.xyz"})");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("cloud.xyz: line 2: expected 6 numbers"), std::string::npos) << r.err;
    fs::remove_all(dir);
}

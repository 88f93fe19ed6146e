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

// n points of the unit sphere (Fibonacci lattice) with outward normals, as XYZ text.
void write_sphere_xyz(const fs::path& file, int n) {
    std::ofstream out(file);
    out << std::setprecision(17) << "# unit sphere, x y z nx ny nz\n";
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
        const double x = r * std::cos(golden * i), y = r * std::sin(golden * i);
        out << x << ' ' << y << ' ' << z << ' ' << x << ' ' << y << ' ' << z << '\n';
    }
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

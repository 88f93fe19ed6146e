// End-to-end: geometry from files (hexmesh run on a surface case, inspect, sdf, bad input).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli.h"

using namespace hexmesh::test_support;
namespace fs = std::filesystem;

namespace {

void expect_one_error_line(const CommandResult& r, const std::string& message) {
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("hexmesh: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
}

}  // namespace

TEST(CliGeometry, RunsTheCapsuleSurfaceCase) {
    const fs::path out = scratch("capsule");
    fs::remove_all(out);
    const CommandResult r = run_hexmesh("run cases/stl_capsule/case.json -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(row_value(r.out, "inverted corner tets"), 0) << r.out;
    EXPECT_TRUE(fs::exists(out / "grid.vtm"));
    fs::remove_all(out);
}

TEST(CliGeometry, FileInsideCsg) {
    const fs::path dir = scratch("csg_file");
    fs::create_directories(dir);
    std::ofstream(dir / "case.json")
        << "{\"geometry\": {\"intersection\": [{\"file\": \"" HEXMESH_SOURCE_DIR
           "/cases/stl_capsule/part.obj\", \"voxel_size\": 0.01},"
           " {\"sphere\": {\"radius\": 0.8}}]},"
           " \"grid\": {\"cells_per_edge\": 8, \"wall_cells\": 6}}";
    const CommandResult r = run_hexmesh("run '" + (dir / "case.json").string() + "' -o '" +
                                        (dir / "out").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(row_value(r.out, "inverted corner tets"), 0) << r.out;
    fs::remove_all(dir);
}

TEST(CliGeometry, InspectPrintsTheDiagnostics) {
    const CommandResult r = run_hexmesh("inspect cases/stl_capsule/part.obj");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(row_value(r.out, "triangles"), 576) << r.out;
    EXPECT_EQ(row_value(r.out, "open (boundary) edges"), 0) << r.out;
    EXPECT_EQ(row_value(r.out, "self-intersecting pairs"), 0) << r.out;
    EXPECT_NE(r.out.find("watertight: yes"), std::string::npos) << r.out;
}

TEST(CliGeometry, SdfWritesAVdbFile) {
    const fs::path vdb = scratch("capsule.vdb");
    fs::remove(vdb);
    const CommandResult r =
        run_hexmesh("sdf cases/stl_capsule/part.obj -o '" + vdb.string() + "' --resolution 64");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("voxel size        0.03125"), std::string::npos) << r.out;
    ASSERT_TRUE(fs::exists(vdb));
    EXPECT_GT(fs::file_size(vdb), 1000u);
    std::ifstream in(vdb, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    EXPECT_EQ(std::string(magic, 4), std::string("\x20\x42\x44\x56", 4));  // OpenVDB magic
    fs::remove(vdb);
}

TEST(CliGeometry, BadSurfacesGiveOneMessage) {
    const fs::path dir = scratch("bad_surfaces");
    fs::create_directories(dir);
    std::ofstream(dir / "empty.stl");
    std::ofstream(dir / "cut.stl", std::ios::binary) << std::string(80, 'x') << std::string("\x05\0\0\0", 4)
                                                     << std::string(70, '\x01');
    std::ofstream(dir / "nan.obj") << "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n";
    std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
    std::ofstream(dir / "cloud.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                        "property float y\nproperty float z\nend_header\n0 0 0\n";
    const std::string d = dir.string() + "/";
    expect_one_error_line(run_hexmesh("inspect '" + d + "missing.stl'"), "missing.stl: cannot open");
    expect_one_error_line(run_hexmesh("inspect '" + d + "empty.stl'"), "empty.stl: empty file");
    expect_one_error_line(run_hexmesh("sdf '" + d + "cut.stl' -o '" + d + "x.vdb'"),
                          "cut.stl: truncated binary STL");
    expect_one_error_line(run_hexmesh("sdf '" + d + "nan.obj' -o '" + d + "x.vdb'"),
                          "nan.obj: line 3: vertex coordinates must be finite");
    expect_one_error_line(run_hexmesh("sdf '" + d + "flat.obj' -o '" + d + "x.vdb'"),
                          "flat.obj: line 4: zero-area triangle");
    expect_one_error_line(run_hexmesh("inspect '" + d + "cloud.ply'"), "cloud.ply: not a surface");
    EXPECT_FALSE(fs::exists(dir / "x.vdb"));
    // A case whose surface file is missing names the resolved path.
    std::ofstream(dir / "case.json") << "{\"geometry\": {\"file\": \"nothere.stl\"}}";
    expect_one_error_line(run_hexmesh("run '" + d + "case.json' -o '" + d + "out'"),
                          d + "nothere.stl: cannot open");
    EXPECT_FALSE(fs::exists(dir / "out"));
    fs::remove_all(dir);
}

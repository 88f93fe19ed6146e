#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli.h"

using namespace hexmesh::test_support;
namespace fs = std::filesystem;

namespace {

// Writes `text` as a case file, runs `hexmesh run` on it and checks the failure contract:
// exit code 1, one line on stderr containing `message`, and no output folder.
void expect_refused(const std::string& name, const std::string& text, const std::string& message) {
    const fs::path dir = scratch("bad_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path file = dir / "case.json";
    if (!text.empty()) std::ofstream(file) << text;
    const fs::path out = dir / "out";
    const CommandResult r = run_hexmesh("run '" + file.string() + "' -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 1) << name;
    EXPECT_EQ(count_lines(r.err), 1) << name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("hexmesh: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << name << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << name;
    fs::remove_all(dir);
}

}  // namespace

TEST(CliErrors, MissingCaseFile) {
    expect_refused("missing", "", "case.json: cannot open case file");
}

TEST(CliErrors, MalformedJson) {
    expect_refused("malformed", "{\"geometry\": {\"sphere\": {\"radius\": 1}},,}",
                   "malformed JSON: parse error at line 1");
}

TEST(CliErrors, WrongKey) {
    expect_refused("wrong_key", R"({"geometry": {"sphere": {"radius": 1}}, "gird": {}})",
                   "gird: unknown key");
}

TEST(CliErrors, NegativeSize) {
    expect_refused("negative", R"({"geometry": {"sphere": {"radius": -2}}})",
                   "geometry.sphere.radius: expected a positive number, got number -2");
}

// A formula's surface is contoured for the map onto the sphere, and its handles counted there.
TEST(CliErrors, BodyThatCannotBeGridded) {
    expect_refused("torus", R"({"geometry": {"torus": {"major_radius": 1, "minor_radius": 0.3}}})",
                   "genus 1: the surface u = 0 (contoured on a lattice of");
}

// A boundary layer whose first cell alone fills more than half of a line: refused at once,
// naming where. (Thinner layers are cut to fit there: CliRun.ThinBodyTakesFewerLayersThere.)
TEST(CliErrors, FirstLayerThickerThanTheBody) {
    const std::string thin = R"({"geometry": {"ellipsoid": {"center": [0, 0, 0],
                                                           "semi_axes": [1, 1, 0.05]}},
        "grid": {"topology": "o-h", "cells_per_edge": 8, "wall_cells": 10},
        "boundary_layer": {"first_height": 0.05, "growth_ratio": 1.3, "layers": 8}})";
    for (const std::string& message :
         {std::string("boundary layer of 8 layers (1.193 thick) does not fit the wall-normal "
                      "line of 10 cells and length "),
          std::string(" from the wall at ("), std::string("not even its first layer (0.05)")})
        expect_refused("thin", thin, message);
}

// Bodies the grid's arithmetic cannot hold, and a first layer too thin for its digits:
// refused at once, each naming its number and the limit.
TEST(CliErrors, BodiesOfAbsurdSizeOrPlace) {
    expect_refused("far", R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1e200}}})",
                   "the body reaches 1e+200 from the origin; hexmesh grids bodies within 1e36 of "
                   "it: give it in larger units");
    expect_refused(
        "small", R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1e-12}}})",
        "the body is 3.46e-12 across; hexmesh grids bodies at least 1e-9 across: give it "
        "in smaller units");
    expect_refused("off", R"({"geometry": {"sphere": {"center": [1e300, 0, 0], "radius": 1}}})",
                   "the body reaches 1e+300 from the origin");
    expect_refused("digits", R"({"geometry": {"sphere": {"center": [1e12, 0, 0], "radius": 1}}})",
                   "the body, 3.46 across, lies 1e+12 from the origin, more than 1e9 times its "
                   "size: its coordinates keep too few digits for its cells; move it nearer the "
                   "origin");
    expect_refused("thin_layer", R"({"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}},
        "boundary_layer": {"first_height": 1e-300, "growth_ratio": 1.2, "layers": 3}})",
                   "boundary_layer.first_height 1e-300 is under 1e-12 of the body's size (3.46)");
}

TEST(CliErrors, QualityOfAMissingMesh) {
    const CommandResult r = run_hexmesh("quality /nonexistent/grid.vtm");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("/nonexistent/grid.vtm: no such mesh file"), std::string::npos) << r.err;
}

TEST(CliErrors, UnknownSubcommandIsAUsageError) {
    const CommandResult r = run_hexmesh("mesh-it-please");
    EXPECT_NE(r.exit_code, 0);
}

TEST(CliErrors, ANestedValueHundredThousandDeepIsDescribedInOneShortLine) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    expect_refused("deep", "{\"geometry\": " + deep + ", \"domain\": \"exterior\"}",
                   "geometry: expected an object, got array [[[[");
}

TEST(CliErrors, WrongArgumentsAreOneLineWithExitCodeOne) {
    for (const std::string& args : {std::string("gci a b c"), std::string("quality x.vtm -o y"),
                                    std::string(""), std::string("no-such-command")}) {
        const CommandResult r = run_hexmesh(args);
        EXPECT_EQ(r.exit_code, 1) << args;
        EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind("hexmesh: error: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find("--help"), std::string::npos) << r.err;
    }
    const CommandResult help = run_hexmesh("run --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("case file"), std::string::npos) << help.out;
}

TEST(CliErrors, ADistanceFieldTooLargeForTheMachineIsRefusedBeforeItIsBuilt) {
    const fs::path dir = scratch("sdf_memory");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path cube = dir / "cube.off";
    std::ofstream(cube) << "OFF\n8 12 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
                           "3 0 2 1\n3 1 2 3\n3 4 5 6\n3 5 7 6\n3 0 1 4\n3 1 5 4\n"
                           "3 2 6 3\n3 3 6 7\n3 0 4 2\n3 2 4 6\n3 1 3 5\n3 3 7 5\n";
    const fs::path out = dir / "cube.vdb";
    CommandResult r =
        run_hexmesh("sdf '" + cube.string() + "' --resolution 100000 -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(cube.string() + ": a distance field of voxel size 1e-05"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find(" GB, more than the limit of"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // The limit can be set: 1 MB refuses what the default allows.
    r = run_hexmesh("--max-memory 0.001 sdf '" + cube.string() + "' --resolution 64 -o '" +
                    out.string() + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(
        r.err.find("more than the limit of 0.001 GB: use a larger voxel size (or --max-memory)"),
        std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out));
    r = run_hexmesh("sdf '" + cube.string() + "' --resolution 64 -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(out));
    fs::remove_all(dir);
}

namespace {

// Whether some process holds the lock `run` takes on its output folder (flock on the folder).
bool folder_locked(const fs::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool locked = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
    ::close(fd);  // releases it if this process got it
    return locked;
}

}  // namespace

TEST(CliErrors, TwoRunsIntoOneFolderAtOnceOneSucceedsTheOtherIsRefused) {
    const fs::path dir = scratch("two_runs");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path out = dir / "out";
    const auto run = [&](const std::string& n) {
        return std::string("'") + HEXMESH_EXE + "' run cases/sphere/case.json -o '" + out.string() +
               "' > '" + (dir / (n + ".out")).string() + "' 2> '" + (dir / (n + ".err")).string() +
               "'; echo $? > '" + (dir / (n + ".rc")).string() + "'";
    };
    // The second starts while the first holds the folder (the sphere takes about a second; on
    // a loaded machine the second could otherwise start after the first has finished).
    ASSERT_EQ(std::system(("(" + run("1") + ") &").c_str()), 0);
    const auto waited = [](const auto& ready) {
        for (int i = 0; i < 6000 && !ready(); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return ready();
    };
    ASSERT_TRUE(waited([&] { return folder_locked(out) || fs::exists(dir / "1.rc"); }));
    ASSERT_FALSE(fs::exists(dir / "1.rc"))
        << "the first run ended before it was seen holding the folder";
    ASSERT_EQ(std::system(run("2").c_str()), 0);
    ASSERT_TRUE(
        waited([&] { return fs::exists(dir / "1.rc") && !read_text(dir / "1.rc").empty(); }));
    const int rc1 = std::stoi(read_text(dir / "1.rc")), rc2 = std::stoi(read_text(dir / "2.rc"));
    EXPECT_EQ(rc1, 0) << read_text(dir / "1.err");
    EXPECT_EQ(rc2, 1);
    const std::string refused = read_text(dir / "2.err");
    EXPECT_EQ(count_lines(refused), 1) << refused;
    EXPECT_NE(refused.find(out.string() + ": another hexmesh process is writing into this folder"),
              std::string::npos)
        << refused;
    EXPECT_TRUE(fs::exists(out / "grid.vtm"));
    EXPECT_TRUE(fs::exists(out / "quality.json"));
    fs::remove_all(dir);
}

TEST(CliErrors, GciRefusesNanAndRatiosNotAboveOneInsteadOfUsingADefault) {
    const std::pair<std::string, std::string> cases[] = {
        {"gci 1 1.1 1.3 --ratio32 nan", "gci: --ratio32 is nan: expected a finite number"},
        {"gci nan 1.1 1.3", "gci: F1 is nan: expected a finite number"},
        {"gci 1 1.1 1.3 --ratio 0.5", "gci: --ratio is 0.5: a refinement ratio must be > 1"},
    };
    for (const auto& [args, message] : cases) {
        const CommandResult r = run_hexmesh(args);
        EXPECT_EQ(r.exit_code, 1) << args;
        EXPECT_EQ(count_lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    }
    const CommandResult ok = run_hexmesh("gci 1 1.1 1.3 --ratio32 1.5");
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_NE(ok.out.find("refinement ratios r21, r32          2 1.5"), std::string::npos)
        << ok.out;
}

TEST(CliErrors, AMeshWhoseFaceIsSharedByThreeCellsIsRefusedNamingTheFile) {
    const fs::path dir = scratch("three_cells");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path mesh = dir / "three.vtk";
    std::string text =
        "# vtk DataFile Version 3.0\nthree hexes\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 "
        "double\n";
    for (int c = 0; c < 8; ++c)
        text += std::to_string(c & 1) + " " + std::to_string((c >> 1) & 1) + " " +
                std::to_string(c >> 2) + "\n";
    text += "CELLS 3 27\n";
    for (int c = 0; c < 3; ++c) text += "8 0 1 3 2 4 5 7 6\n";
    text += "CELL_TYPES 3\n12\n12\n12\n";
    std::ofstream(mesh) << text;
    for (const std::string& command :
         {"quality '" + mesh.string() + "'",
          "untangle '" + mesh.string() + "' -o '" + (dir / "out.vtu").string() + "'"}) {
        const CommandResult r = run_hexmesh(command);
        EXPECT_EQ(r.exit_code, 1) << command;
        EXPECT_EQ(count_lines(r.err), 1) << r.err;
        EXPECT_NE(
            r.err.find(mesh.string() + ": a face is shared by more than two cells (cells 0, 1, 2)"),
            std::string::npos)
            << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "out.vtu"));
    fs::remove_all(dir);
}

TEST(CliOutput, ARunIntoTheCurrentFolderKeepsItsOtherFiles) {
    // The current folder cannot take the staged result's place by a rename: the outputs move
    // in one by one, the folder's own files and folders untouched.
    const fs::path dir = scratch("current_folder");
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "sub" / "file.txt") << "keep";
    std::ofstream(dir / "notes.txt") << "mine";
    const fs::path case_file = fs::absolute("cases/sphere/case.json");
    const CommandResult r = run_command("cd '" + dir.string() + "' && '" + HEXMESH_EXE + "' run '" +
                                        case_file.string() + "' -o .");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "grid.vtm"));
    EXPECT_EQ(read_text(dir / "sub" / "file.txt"), "keep");
    EXPECT_EQ(read_text(dir / "notes.txt"), "mine");
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find("staging"), std::string::npos) << e.path();
    fs::remove_all(dir);
}

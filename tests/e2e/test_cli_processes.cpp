// `mpirun -np N hexmesh refine`: the refined grid made by several processes, each its share of
// the blocks, is the grid one process makes, bit for bit; its OpenFOAM case comes decomposed,
// one processor folder per process, and OpenFOAM's parallel tools take it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "io/vtk_mesh.h"

using namespace hexmesh;
using namespace hexmesh::test_support;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

#ifdef HEXMESH_TEST_MPIRUN
// mpirun as the tests run it: as root too (a container's CI), more processes than cores.
std::string mpirun(int processes) {
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " HEXMESH_TEST_MPIRUN
           " --oversubscribe -np " +
           std::to_string(processes) + " '" + HEXMESH_EXE + "' ";
}
#endif

const fs::path coarse_dir = scratch("coarse");

fs::path refined(int processes) {
    return scratch("refined_" + std::to_string(processes));
}

// The bundled sphere case's grid (32 000 cells), refined once by one process and by 2 and 3
// (more than the cores of a small machine: oversubscribed).
class RefineOnProcesses : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
#ifdef HEXMESH_TEST_MPIRUN
        run = run_hexmesh("run cases/sphere/case.json -o '" + coarse_dir.string() + "'");
        const std::string grid = "'" + (coarse_dir / "grid.vtm").string() + "'";
        serial = run_hexmesh("refine " + grid + " -o '" + refined(1).string() +
                             "' --format openfoam --format gmsh");
        for (int n : {2, 3})
            parallel[n - 2] =
                run_command(mpirun(n) + "refine " + grid + " -o '" + refined(n).string() +
                            "' --format openfoam --format gmsh");
#endif
    }
    void SetUp() override {
#ifndef HEXMESH_TEST_MPIRUN
        GTEST_SKIP() << "hexmesh was built without MPI (libopenmpi-dev): nothing to run on "
                        "several processes";
#endif
    }
    static CommandResult run, serial, parallel[2];
};
CommandResult RefineOnProcesses::run, RefineOnProcesses::serial, RefineOnProcesses::parallel[2];

}  // namespace

TEST_F(RefineOnProcesses, EveryBlockIsTheSerialOneBitForBit) {
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    ASSERT_EQ(serial.exit_code, 0) << serial.out << serial.err;
    const fs::path pieces = refined(1) / "grid";
    int blocks = 0;
    for (const auto& entry : fs::directory_iterator(pieces)) {
        ++blocks;
        const std::string one = read_text(entry.path());
        for (int n : {2, 3}) {
            const fs::path other = refined(n) / "grid" / entry.path().filename();
            ASSERT_TRUE(fs::exists(other)) << other;
            EXPECT_TRUE(read_text(other) == one) << other << " differs from " << entry.path();
        }
    }
    EXPECT_EQ(blocks, 7);  // the O-H grid: a core and six wall blocks
    for (int n : {2, 3})
        EXPECT_EQ(read_text(refined(n) / "grid.vtm"), read_text(refined(1) / "grid.vtm"));
}

TEST_F(RefineOnProcesses, AFormatGatheredAtTheFirstProcessIsTheSerialFile) {
    const std::string one = read_text(refined(1) / "grid.msh");
    ASSERT_GT(one.size(), 1000u);
    for (int n : {2, 3}) EXPECT_TRUE(read_text(refined(n) / "grid.msh") == one) << n;
}

#ifdef HEXMESH_TEST_MPIRUN
namespace {

// An OpenFOAM tool on `processes` processes (1: without mpirun) on the case `dir`.
CommandResult foam(int processes, const std::string& tool, const fs::path& dir) {
    const std::string env =
        std::getenv("WM_PROJECT_DIR") ? "" : "WM_PROJECT_DIR=/usr/share/openfoam ";
    if (processes == 1) return run_command(env + tool + " -case '" + dir.string() + "'");
    return run_command(env + "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                       HEXMESH_TEST_MPIRUN " --oversubscribe -np " + std::to_string(processes) +
                       " " + tool + " -parallel -case '" + dir.string() + "'");
}

// The number checkMesh prints after `name` (e.g. "cells:").
long long mesh_count(const std::string& out, const std::string& name) {
    const size_t at = out.find(name);
    return at == std::string::npos ? -1 : std::stoll(out.substr(at + name.size()));
}

}  // namespace

// More processes than blocks (9 for 7): the largest blocks are split between processes, each
// writing its part as a piece of its own; the grid read back is the serial one, and the
// OpenFOAM case is decomposed across the cuts too.
TEST_F(RefineOnProcesses, OnMoreProcessesThanBlocksSplitBlocksGiveTheSameGrid) {
    const CommandResult r =
        run_command(mpirun(9) + "refine '" + (coarse_dir / "grid.vtm").string() + "' -o '" +
                    refined(9).string() + "' --format gmsh --format openfoam");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find(" along "), std::string::npos) << r.out;  // a part of a block
    EXPECT_EQ(r.out.find("no block"), std::string::npos) << r.out;
    const BlockGrid one = read_vtk_block_grid((refined(1) / "grid.vtm").string());
    const BlockGrid nine = read_vtk_block_grid((refined(9) / "grid.vtm").string());
    EXPECT_EQ(nine.blocks.size(), 9u);
    EXPECT_EQ(nine.num_cells(), one.num_cells());
    auto sorted = [](std::vector<Vec3> p) {
        std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
            return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
        });
        return p;
    };
    EXPECT_TRUE(sorted(nine.points) == sorted(one.points));
    EXPECT_TRUE(read_text(refined(9) / "grid.msh") == read_text(refined(1) / "grid.msh"));
    const json a = json::parse(read_text(refined(1) / "quality.json"));
    const json b = json::parse(read_text(refined(9) / "quality.json"));
    for (const char* key : {"cells", "inverted_corner_tets", "min_scaled_jacobian", "worst_cell",
                            "max_non_orthogonality_deg"})
        EXPECT_EQ(b.at(key), a.at(key)) << key;
    // The decomposed case: processor patches across the cuts too.
    const fs::path dir = refined(9) / "grid_openfoam";
    EXPECT_TRUE(fs::exists(dir / "processor8" / "constant" / "polyMesh" / "boundary"));
    const CommandResult mesh = foam(9, "checkMesh", dir);
    EXPECT_NE(mesh.out.find("Mesh OK."), std::string::npos) << mesh.out << mesh.err;
    EXPECT_NE(mesh.out.find("Coupled point location match (average 0) OK."), std::string::npos);
}
#endif

TEST_F(RefineOnProcesses, TheReportIsTheSerialOne) {
    for (int n : {2, 3}) {
        const CommandResult& r = parallel[n - 2];
        ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
        EXPECT_NE(r.out.find("(" + std::to_string(n) + " processes)"), std::string::npos) << r.out;
        // Each process's blocks listed, each block once.
        EXPECT_NE(r.out.find("process " + std::to_string(n - 1) + ":"), std::string::npos);
        EXPECT_EQ(count_lines(r.out) - count_lines(serial.out), n /* "process r:" lines */);
        const json one = json::parse(read_text(refined(1) / "quality.json"));
        const json many = json::parse(read_text(refined(n) / "quality.json"));
        for (const char* key : {"cells", "inverted_corner_tets", "min_scaled_jacobian",
                                "max_non_orthogonality_deg", "max_skewness"})
            EXPECT_EQ(many.at(key), one.at(key)) << key << ", " << n << " processes";
        // Means are sums merged in another order: equal to rounding.
        EXPECT_NEAR(many.at("mean_scaled_jacobian").get<double>(),
                    one.at("mean_scaled_jacobian").get<double>(), 1e-12);
        EXPECT_EQ(many.at("wall").at("cells"), one.at("wall").at("cells"));
        EXPECT_TRUE(fs::exists(refined(n) / "report.html"));
        EXPECT_TRUE(fs::exists(refined(n) / "grid.case.json"));
    }
}

#ifdef HEXMESH_TEST_MPIRUN
TEST_F(RefineOnProcesses, TheOpenFoamCaseComesDecomposedAndCheckMeshPassesInParallel) {
    for (int n : {2, 3}) {
        const fs::path dir = refined(n) / "grid_openfoam";
        for (int r = 0; r < n; ++r)
            EXPECT_TRUE(fs::exists(dir / ("processor" + std::to_string(r)) / "constant" /
                                   "polyMesh" / "boundary"))
                << r;
        EXPECT_FALSE(fs::exists(dir / ("processor" + std::to_string(n))));
        EXPECT_NE(read_text(dir / "system" / "decomposeParDict")
                      .find("numberOfSubdomains " + std::to_string(n) + ";"),
                  std::string::npos);
        const CommandResult mesh = foam(n, "checkMesh", dir);
        EXPECT_NE(mesh.out.find("Mesh OK."), std::string::npos) << mesh.out << mesh.err;
        EXPECT_NE(mesh.out.find("Coupled point location match (average 0) OK."), std::string::npos)
            << mesh.out;
    }
}

TEST_F(RefineOnProcesses, ReconstructedItIsTheSerialGridsCellsAndFaces) {
    const CommandResult one = foam(1, "checkMesh", refined(1) / "grid_openfoam");
    ASSERT_NE(one.out.find("Mesh OK."), std::string::npos) << one.out << one.err;
    for (int n : {2, 3}) {
        const fs::path dir = refined(n) / "grid_openfoam";
        const CommandResult joined = foam(1, "reconstructParMesh -constant", dir);
        ASSERT_EQ(joined.exit_code, 0) << joined.out << joined.err;
        const CommandResult mesh = foam(1, "checkMesh", dir);
        EXPECT_NE(mesh.out.find("Mesh OK."), std::string::npos) << mesh.out << mesh.err;
        for (const char* count : {"points:", "faces:", "internal faces:", "cells:"})
            EXPECT_EQ(mesh_count(mesh.out, count), mesh_count(one.out, count)) << count << n;
    }
}

TEST_F(RefineOnProcesses, SimpleFoamRunsOnTheDecomposedCase) {
    const fs::path dir = refined(2) / "grid_openfoam";
    // Two iterations are enough to read every processor's mesh and fields and exchange
    // across the processor patches.
    std::string control = read_text(dir / "system" / "controlDict");
    const size_t at = control.find("endTime ");
    ASSERT_NE(at, std::string::npos);
    control.replace(at, control.find(';', at) - at, "endTime 2");
    std::ofstream(dir / "system" / "controlDict") << control;
    const CommandResult solve = foam(2, "simpleFoam", dir);
    EXPECT_EQ(solve.exit_code, 0) << solve.out << solve.err;
    EXPECT_NE(solve.out.find("Solving for p"), std::string::npos) << solve.out;
    EXPECT_NE(solve.out.find("End"), std::string::npos) << solve.out;
}

TEST(CommandsOnProcesses, OnlyRefineRunsOnSeveralAndTheRefusalIsSaidOnce) {
    const CommandResult r =
        run_command(mpirun(2) + "quality '" HEXMESH_SOURCE_DIR "/cases/bean/bean.stl'");
    EXPECT_NE(r.exit_code, 0);
    const std::string line = "hexmesh: error: only `refine` runs on several processes";
    const size_t at = r.err.find(line);
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(line, at + 1), std::string::npos) << r.err;
}
#endif

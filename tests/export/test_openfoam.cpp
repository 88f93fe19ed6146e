#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <vector>

#include "export_test_support.h"
#include "hexmesh/pipeline/run_case.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/case_file.h"
#include "io/fluent_mesh.h"
#include "io/openfoam_mesh.h"
#include "volume/o_grid.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

// The number token after `label` in checkMesh's output, as printed ("" if absent).
std::string token_after(const std::string& text, const std::string& label) {
    const auto at = text.find(label);
    if (at == std::string::npos) return "";
    const std::string rest = text.substr(at + label.size());
    std::smatch m;
    if (!std::regex_search(rest, m,
                           std::regex(R"(^\s*([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?))")))
        return "";
    return m[1];
}

// True when `ours` agrees with `printed`, a number checkMesh wrote with its stream's default
// 6 significant digits: |ours - printed| <= half a unit of the 6th significant digit of
// printed (plus 1e-12 relative slack for the text round trip).
bool equal_to_printed_digits(const std::string& printed, double ours) {
    if (printed.empty()) return false;
    const double v = std::strtod(printed.c_str(), nullptr);
    if (v == 0) return ours == 0;
    const double unit = std::pow(10.0, std::floor(std::log10(std::fabs(v))) - 5);
    return std::fabs(ours - v) <= 0.5 * unit + 1e-12 * std::fabs(v);
}

std::string full(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

struct FoamPatch {
    std::string name, type;
    long n_faces = -1, start_face = -1;
};

// The entries of constant/polyMesh/boundary (name, type, nFaces, startFace), in file order,
// and the list size the file declares (-1 if unreadable).
std::vector<FoamPatch> read_foam_boundary(const fs::path& file, long& declared) {
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    declared = -1;
    std::smatch m;
    // The list size is the first bare integer after the FoamFile header's closing brace.
    const auto header_end = text.find("}");
    if (header_end != std::string::npos) {
        const std::string body = text.substr(header_end + 1);
        if (std::regex_search(body, m, std::regex(R"((\d+)\s*\()"))) declared = std::stol(m[1]);
    }
    std::vector<FoamPatch> patches;
    const std::regex entry(
        R"((\w+)\s*\{\s*type\s+(\w+);[^}]*?nFaces\s+(\d+);\s*startFace\s+(\d+);\s*\})");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), entry);
         it != std::sregex_iterator(); ++it)
        patches.push_back({(*it)[1], (*it)[2], std::stol((*it)[3]), std::stol((*it)[4])});
    return patches;
}

// The exterior O-grid of the unit sphere out to a far field of size 10 (sphere radius or box
// half-size): n = 12, 24 layers, a boundary layer of 6 cells from 0.01 growing by 1.2.
BlockGrid exterior_o_grid(FarFieldShape shape) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    OGridOptions o;
    o.cells_per_edge = 12;
    o.layers = 24;
    o.wall_layers = WallLayers{0.01, 1.2, 6};
    o.far_field = shape;
    o.far_field_size = 10;
    return make_o_grid(sphere, o);
}

// Writes the exterior O-grid as an OpenFOAM case, runs checkMesh on it and checks what the
// export issue asks: "Mesh OK.", our cell count, min volume and max non-orthogonality to the
// digits checkMesh prints, and exactly the patches wall (type wall) and farfield (type patch),
// 6 n^2 faces each, in the boundary file and as checkMesh reads them.
void check_exterior_o_grid(FarFieldShape shape, const std::string& name) {
    const BlockGrid grid = exterior_o_grid(shape);
    const int n = 12, layers = 24;
    ASSERT_EQ(grid.blocks.size(), 6u);
    const QualityReport q = measure_quality(to_hex_mesh(grid));
    ASSERT_EQ(q.cells, 6 * n * n * layers);
    ASSERT_EQ(q.inverted_cells, 0);

    const fs::path case_dir = scratch(name) / "case";
    write_openfoam_mesh(grid, case_dir.string());
    const ToolRun r = run_tool(check_mesh_command(case_dir));
    std::ofstream((case_dir.parent_path() / "checkMesh.log").string()) << r.output;  // to inspect
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Mesh OK."), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Failed"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("***"), std::string::npos) << r.output;  // no failed check at all
    EXPECT_NE(r.output.find("Upper triangular ordering OK."), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Boundary definition OK."), std::string::npos) << r.output;

    EXPECT_EQ(number_after(r.output, "    cells:"), double(q.cells)) << r.output;
    const std::string min_volume = token_after(r.output, "Min volume = ");
    EXPECT_TRUE(equal_to_printed_digits(min_volume, q.min_volume))
        << "checkMesh min volume " << min_volume << ", ours " << full(q.min_volume);
    const std::string non_orth = token_after(r.output, "Mesh non-orthogonality Max: ");
    EXPECT_TRUE(equal_to_printed_digits(non_orth, q.max_non_orthogonality_deg))
        << "checkMesh max non-orthogonality " << non_orth << ", ours "
        << full(q.max_non_orthogonality_deg);

    // Beyond the issue's list, skewness and aspect ratio agree to the printed digits as well.
    // The boundary layer's aspect ratio (first height 0.01 against a tangential spacing of
    // about 0.13) stays far under checkMesh's threshold of 1000, so no check may fail.
    const std::string skewness = token_after(r.output, "Max skewness = ");
    EXPECT_TRUE(equal_to_printed_digits(skewness, q.max_skewness))
        << "checkMesh max skewness " << skewness << ", ours " << full(q.max_skewness);
    const std::string aspect = token_after(r.output, "Max aspect ratio = ");
    EXPECT_TRUE(equal_to_printed_digits(aspect, q.max_aspect_ratio))
        << "checkMesh max aspect ratio " << aspect << ", ours " << full(q.max_aspect_ratio);

    // The boundary file: exactly wall and farfield, 6 n^2 faces each, after the internal faces.
    long declared = -1;
    const std::vector<FoamPatch> patches =
        read_foam_boundary(case_dir / "constant" / "polyMesh" / "boundary", declared);
    EXPECT_EQ(declared, 2);
    ASSERT_EQ(patches.size(), 2u);
    long start = patches[0].start_face;
    for (const FoamPatch& p : patches) {
        SCOPED_TRACE(p.name);
        EXPECT_TRUE(p.name == "wall" || p.name == "farfield");
        EXPECT_EQ(p.type, p.name == "wall" ? "wall" : "patch");
        EXPECT_EQ(p.n_faces, 6L * n * n);
        EXPECT_EQ(p.start_face, start);
        start += p.n_faces;
    }
    EXPECT_NE(patches[0].name, patches[1].name);
    // Every face of a hex is shared by two cells except the 2 * 6 n^2 boundary faces.
    EXPECT_EQ(patches[0].start_face, (6L * q.cells - 2 * 6L * n * n) / 2);
    EXPECT_EQ(number_after(r.output, "    boundary patches:"), 2.0) << r.output;
    // checkMesh's own patch table: each patch a closed, singly connected surface.
    for (const char* patch : {"wall", "farfield"}) {
        std::smatch m;
        EXPECT_TRUE(
            std::regex_search(r.output, m,
                              std::regex(std::string(R"(\n\s*)") + patch +
                                         R"(\s+(\d+)\s+(\d+)\s+ok \(closed singly connected\))")))
            << patch << "\n"
            << r.output;
        if (!m.empty()) {
            EXPECT_EQ(std::stol(m[1]), 6L * n * n) << patch;
            EXPECT_EQ(std::stol(m[2]), 6L * n * n + 2) << patch;
        }
    }
}

}  // namespace

// The sphere case through the pipeline with outputs ["openfoam"]; checkMesh must say
// "Mesh OK." and agree with our cell count, min volume and max non-orthogonality (our
// metrics follow OpenFOAM's definitions). checkMesh prints 6 significant digits.
TEST(OpenFoam, CheckMeshAcceptsTheSphereGridAndAgreesWithOurMetrics) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    Case c = read_case(HEXMESH_SOURCE_DIR "/cases/sphere/case.json");
    c.outputs = {"vtk", "openfoam"};
    const fs::path dir = scratch("openfoam");
    std::ostringstream log;
    const RunResult result = run_case(c, (dir / "out").string(), RunOptions{}, log);
    const fs::path case_dir = dir / "out" / "grid_openfoam";
    ASSERT_TRUE(fs::exists(case_dir / "constant" / "polyMesh" / "faces"));
    ASSERT_TRUE(fs::exists(case_dir / "system" / "controlDict"));

    const ToolRun r = run_tool(check_mesh_command(case_dir));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Mesh OK."), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("***"), std::string::npos) << r.output;  // no failed check at all

    const QualityReport& q = result.report.quality;
    EXPECT_EQ(number_after(r.output, "    cells:"), double(q.cells));
    const double min_volume = number_after(r.output, "Min volume = ");
    EXPECT_NEAR(min_volume, q.min_volume, 1e-5 * q.min_volume) << r.output;
    const double non_orth = number_after(r.output, "Mesh non-orthogonality Max: ");
    EXPECT_NEAR(non_orth, q.max_non_orthogonality_deg, 1e-4 * q.max_non_orthogonality_deg)
        << r.output;
    EXPECT_NEAR(number_after(r.output, "Max skewness = "), q.max_skewness, 1e-5 * q.max_skewness);
    EXPECT_NEAR(number_after(r.output, "Max aspect ratio = "), q.max_aspect_ratio,
                1e-3 * q.max_aspect_ratio);
    EXPECT_NE(r.output.find("Upper triangular ordering OK."), std::string::npos);
    EXPECT_NE(r.output.find("Boundary definition OK."), std::string::npos);
}

// Every bundled case through the pipeline: when our report calls the grid valid (no inverted
// corner tet and none of the cell checks a solver fails), checkMesh says "Mesh OK." and fails
// no check.
class BundledCaseInOpenFoam : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledCaseInOpenFoam, ValidByOurReportMeansMeshOkByCheckMesh) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    Case c = read_case(std::string(HEXMESH_SOURCE_DIR "/cases/") + GetParam() + "/case.json");
    c.outputs = {"vtk", "openfoam"};
    c.refinement.levels = 1;
    const fs::path dir = scratch("bundled_" + GetParam());
    RunOptions options;
    options.report = false;
    std::ostringstream log;
    const RunResult result = run_case(c, (dir / "out").string(), options, log);
    ASSERT_TRUE(result.report.quality.solver_valid())
        << GetParam() << ": the bundled case is refused";
    const ToolRun r = run_tool(check_mesh_command(dir / "out" / "grid_openfoam"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Mesh OK."), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("***"), std::string::npos) << r.output;
    fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Cases, BundledCaseInOpenFoam,
                         ::testing::Values("sphere", "sphere_exterior", "ellipsoid", "bean",
                                           "bean_exterior", "box_exterior", "box_cylinder",
                                           "stl_capsule"));

// The exterior O-grid (six shell blocks, patch wall on the sphere, farfield on a sphere of
// radius 10) with a boundary layer of first height 0.01: checkMesh passes every check.
TEST(OpenFoam, CheckMeshAcceptsTheExteriorOGridWithSphereFarField) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    check_exterior_o_grid(FarFieldShape::sphere, "openfoam_o_grid_sphere");
}

// The same with a box far field of half-size 10.
TEST(OpenFoam, CheckMeshAcceptsTheExteriorOGridWithBoxFarField) {
    if (!have_tool("checkMesh"))
        GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
    check_exterior_o_grid(FarFieldShape::box, "openfoam_o_grid_box");
}

namespace {

// Every file under `dir`, relative, sorted.
std::vector<std::string> files_under(const fs::path& dir) {
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files.push_back(fs::relative(e.path(), dir).string());
    std::sort(files.begin(), files.end());
    return files;
}

std::string file_text(const fs::path& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The initial residuals simpleFoam printed for `field` ("Ux", "p", ...), in order.
std::vector<double> initial_residuals(const std::string& log, const std::string& field) {
    std::vector<double> r;
    const std::regex line("Solving for " + field + ", Initial residual = ([0-9.eE+-]+)");
    for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator();
         ++it)
        r.push_back(std::stod((*it)[1]));
    return r;
}

// simpleFoam on the case for `steps` iterations (controlDict's endTime set so).
ToolRun simple_foam(const fs::path& case_dir, int steps) {
    const fs::path control = case_dir / "system" / "controlDict";
    std::string text = file_text(control);
    text = std::regex_replace(text, std::regex(R"(endTime\s+\d+;)"),
                              "endTime         " + std::to_string(steps) + ";");
    std::ofstream(control) << text;
    return run_tool(openfoam_command("simpleFoam -case '" + case_dir.string() + "'"));
}

// The grid written as a Fluent mesh DIR/grid.msh, then converted by OpenFOAM's
// fluent3DMeshToFoam into the case DIR/case (whose dictionaries an OpenFOAM export provides).
ToolRun fluent_through_openfoam(const BlockGrid& grid, const fs::path& dir) {
    write_openfoam_mesh(grid, (dir / "case").string());
    fs::remove_all(dir / "case" / "constant" / "polyMesh");
    write_fluent_mesh(grid, (dir / "grid.msh").string());
    return run_tool(openfoam_command("fluent3DMeshToFoam -case '" + (dir / "case").string() +
                                     "' '" + (dir / "grid.msh").string() + "'"));
}

}  // namespace

// The bundled exterior sphere case through `run` (outputs vtk and openfoam), then its grid.vtm
// through `export`: the two case folders are the same, file for file and byte for byte, and
// simpleFoam runs the exported one as written (laminar, Re = 100) for 20 iterations with no
// error, the velocity and pressure residuals falling by more than 20 times.
TEST(OpenFoam, RunAndExportWriteTheSameCaseAndSimpleFoamRunsIt) {
    if (!have_tool("simpleFoam"))
        GTEST_SKIP() << "simpleFoam not installed (Debian package openfoam)";
    const fs::path dir = scratch("simplefoam");
    const std::string exe = HEXMESH_EXE;
    const ToolRun run =
        run_tool("cd '" HEXMESH_SOURCE_DIR "' && '" + exe +
                 "' run cases/sphere_exterior/case.json -o '" + (dir / "run").string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const fs::path from_run = dir / "run" / "grid_openfoam", from_export = dir / "exported";
    const ToolRun ex = run_tool("'" + exe + "' export '" + (dir / "run" / "grid.vtm").string() +
                                "' --format openfoam -o '" + from_export.string() + "'");
    ASSERT_EQ(ex.exit_code, 0) << ex.output;
    EXPECT_NE(ex.output.find("flow: velocity (1, 0, 0), density 1, viscosity 0.01, laminar (from "),
              std::string::npos)
        << ex.output;
    const std::vector<std::string> files = files_under(from_run);
    EXPECT_EQ(files, files_under(from_export));
    EXPECT_EQ(files, (std::vector<std::string>{
                         "0/U", "0/p", "constant/polyMesh/boundary", "constant/polyMesh/faces",
                         "constant/polyMesh/neighbour", "constant/polyMesh/owner",
                         "constant/polyMesh/points", "constant/transportProperties",
                         "constant/turbulenceProperties", "system/controlDict", "system/fvSchemes",
                         "system/fvSolution"}));
    for (const std::string& f : files)
        EXPECT_EQ(file_text(from_run / f), file_text(from_export / f)) << f;

    const ToolRun foam = simple_foam(from_export, 20);
    ASSERT_EQ(foam.exit_code, 0) << foam.output;
    EXPECT_EQ(foam.output.find("FOAM FATAL"), std::string::npos) << foam.output;
    EXPECT_NE(foam.output.find("\nEnd"), std::string::npos) << foam.output;
    for (const char* field : {"Ux", "p"}) {
        const std::vector<double> r = initial_residuals(foam.output, field);
        ASSERT_GE(r.size(), 20u) << field << "\n" << foam.output;
        EXPECT_LT(r.back(), r.front() / 20) << field << ": " << r.front() << " -> " << r.back();
    }
}

// A turbulent flow (k-omega SST) from a case file's "flow": the k, omega and nut fields with
// wall functions on the wall and inletOutlet on the far field, k and omega from the intensity
// and mixing length; simpleFoam runs 5 iterations of it with no error.
TEST(OpenFoam, TurbulentFlowFromTheCaseFileRuns) {
    if (!have_tool("simpleFoam"))
        GTEST_SKIP() << "simpleFoam not installed (Debian package openfoam)";
    const fs::path dir = scratch("simplefoam_sst");
    const BlockGrid grid = small_o_h_grid(6, 4);
    FlowSpec flow;
    flow.velocity = Vec3(0, 0, 20);
    flow.viscosity = 1.8e-5;
    flow.density = 1.2;
    flow.turbulence = "k-omega-sst";
    flow.turbulence_intensity = 0.05;
    flow.turbulence_length = 0.1;
    write_openfoam_mesh(grid, (dir / "case").string(), flow);
    const std::string k = file_text(dir / "case" / "0" / "k"),
                      omega = file_text(dir / "case" / "0" / "omega");
    // k = 1.5 (0.05 * 20)^2 = 1.5; omega = sqrt(1.5) / (0.09^0.25 * 0.1) = 22.36...
    EXPECT_NE(k.find("internalField   uniform 1.5"), std::string::npos) << k;
    EXPECT_NE(k.find("kqRWallFunction"), std::string::npos) << k;
    EXPECT_NE(omega.find("internalField   uniform 22.36"), std::string::npos) << omega;
    EXPECT_NE(file_text(dir / "case" / "constant" / "transportProperties")
                  .find("nu              1.5e-05;"),
              std::string::npos);
    EXPECT_NE(file_text(dir / "case" / "constant" / "turbulenceProperties").find("kOmegaSST"),
              std::string::npos);
    const ToolRun foam = simple_foam(dir / "case", 5);
    ASSERT_EQ(foam.exit_code, 0) << foam.output;
    EXPECT_EQ(foam.output.find("FOAM FATAL"), std::string::npos) << foam.output;
    EXPECT_EQ(initial_residuals(foam.output, "k").size(), 5u) << foam.output;
}

// The Fluent mesh of the exterior O-grid through OpenFOAM's own converter (fluent3DMeshToFoam,
// an independent reader of the format): checkMesh says "Mesh OK." with the grid's cells and the
// patches wall and farfield, 6 n^2 faces each (a face turned the wrong way would show as
// wrongly oriented face pyramids and negative volumes).
TEST(Fluent, OpenFoamsConverterReadsAValidMeshWithThePatches) {
    if (!have_tool("fluent3DMeshToFoam") || !have_tool("checkMesh"))
        GTEST_SKIP() << "fluent3DMeshToFoam / checkMesh not installed (Debian package openfoam)";
    const int n = 6;
    const BlockGrid grid = small_o_grid(n, 8, 10);
    const fs::path dir = scratch("fluent");
    const ToolRun convert = fluent_through_openfoam(grid, dir);
    ASSERT_EQ(convert.exit_code, 0) << convert.output;
    EXPECT_NE(convert.output.find("Zone: 4 name: wall type: wall"), std::string::npos)
        << convert.output;
    EXPECT_NE(convert.output.find("Zone: 5 name: farfield type: pressure-far-field"),
              std::string::npos)
        << convert.output;
    const ToolRun r = run_tool(check_mesh_command(dir / "case"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Mesh OK."), std::string::npos) << r.output;
    EXPECT_EQ(number_after(r.output, "    cells:"), double(grid.num_cells()));
    for (const char* patch : {"wall", "farfield"})
        EXPECT_TRUE(
            std::regex_search(r.output, std::regex(std::string(R"(\n\s*)") + patch + R"(\s+)" +
                                                   std::to_string(6 * n * n) + R"(\s)")))
            << patch << "\n"
            << r.output;
}

// Ten patches: Fluent zones 4 to 13, hexadecimal (4 .. d) in the face sections' headers and
// decimal in the zone names' section; OpenFOAM's converter pairs every zone with its name.
TEST(Fluent, ZonesBeyondNineKeepTheirNames) {
    if (!have_tool("fluent3DMeshToFoam") || !have_tool("checkMesh"))
        GTEST_SKIP() << "fluent3DMeshToFoam / checkMesh not installed (Debian package openfoam)";
    // Two blocks of 2 x 2 x 2 cells side by side along x, each outer face its own patch.
    BlockGrid grid;
    for (int k = 0; k <= 2; ++k)
        for (int j = 0; j <= 2; ++j)
            for (int i = 0; i <= 4; ++i) grid.points.emplace_back(i, j, k);
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    for (int b = 0; b < 2; ++b) {
        Block block;
        block.name = fmt::format("b{}", b);
        block.nodes = Dims{3, 3, 3};
        for (int k = 0; k <= 2; ++k)
            for (int j = 0; j <= 2; ++j)
                for (int i = 0; i <= 2; ++i)
                    block.node_ids.push_back(Id(2 * b + i + 5 * (j + 3 * k)));
        for (int f = 0; f < 6; ++f) block.face_patch[f] = fmt::format("p{}", 6 * b + f);
        block.face_patch[b == 0 ? 1 : 0] = "";  // the shared face
        grid.blocks.push_back(block);
    }
    const fs::path dir = scratch("fluent_zones");
    const ToolRun convert = fluent_through_openfoam(grid, dir);
    ASSERT_EQ(convert.exit_code, 0) << convert.output;
    const ToolRun r = run_tool(check_mesh_command(dir / "case"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Mesh OK."), std::string::npos) << r.output;
    for (const char* patch : {"p0", "p2", "p3", "p4", "p5", "p7", "p8", "p9", "p10", "p11"})
        EXPECT_TRUE(
            std::regex_search(r.output, std::regex(std::string(R"(\n\s*)") + patch + R"(\s+4\s)")))
            << patch << "\n"
            << r.output;
}

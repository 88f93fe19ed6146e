#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "export_test_support.h"
#include "hexmesh/pipeline/run_case.h"
#include "io/case_file.h"

using namespace hexmesh;
using namespace hexmesh::test_export;

namespace {

// The number after `label` in checkMesh's output, or NaN.
double number_after(const std::string& text, const std::string& label) {
    const auto at = text.find(label);
    if (at == std::string::npos) return std::nan("");
    return std::strtod(text.c_str() + at + label.size(), nullptr);
}

// checkMesh, with WM_PROJECT_DIR pointing at Debian's OpenFOAM etc/ folder when the
// environment has not set it (the package's binaries need it and nothing else).
std::string check_mesh_command(const fs::path& case_dir) {
    std::string env;
    if (!std::getenv("WM_PROJECT_DIR") && fs::exists("/usr/share/openfoam/etc/controlDict"))
        env = "WM_PROJECT_DIR=/usr/share/openfoam ";
    return env + "checkMesh -case '" + case_dir.string() + "'";
}

}  // namespace

// The sphere case through the pipeline with outputs ["openfoam"]; checkMesh must say
// "Mesh OK." and agree with our cell count, min volume and max non-orthogonality (our
// metrics follow OpenFOAM's definitions). checkMesh prints 6 significant digits.
TEST(OpenFoam, CheckMeshAcceptsTheSphereGridAndAgreesWithOurMetrics) {
    if (!have_tool("checkMesh")) GTEST_SKIP() << "checkMesh not installed (Debian package openfoam)";
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
    EXPECT_NEAR(non_orth, q.max_non_orthogonality_deg, 1e-4 * q.max_non_orthogonality_deg) << r.output;
    EXPECT_NEAR(number_after(r.output, "Max skewness = "), q.max_skewness, 1e-5 * q.max_skewness);
    EXPECT_NEAR(number_after(r.output, "Max aspect ratio = "), q.max_aspect_ratio, 1e-3 * q.max_aspect_ratio);
    EXPECT_NE(r.output.find("Upper triangular ordering OK."), std::string::npos);
    EXPECT_NE(r.output.find("Boundary definition OK."), std::string::npos);
}

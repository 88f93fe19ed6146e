// hexmesh: structured hexahedral grids for CFD from implicit bodies (command-line entry).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <iostream>

#include "hexmesh/pipeline/run_case.h"
#include "io/case_file.h"
#include "io/quality_report.h"
#include "io/vtk_mesh.h"

namespace {

int run(const std::string& case_path, const std::string& outdir, bool keep_invalid) {
    const hexmesh::Case c = hexmesh::read_case(case_path);
    std::cout << fmt::format("hexmesh run {}\n", case_path);
    hexmesh::RunOptions options;
    options.keep_invalid = keep_invalid;
    const hexmesh::RunResult result = hexmesh::run_case(c, outdir, options, std::cout);
    std::cout << "\n" << hexmesh::format_quality_table(result.report) << "\n";
    for (const std::string& f : result.files) std::cout << "written: " << f << "\n";
    return result.report.quality.inverted_corner_tets == 0 ? 0 : 3;
}

int quality(const std::string& mesh_path, bool json) {
    hexmesh::GridReport report;
    report.quality = hexmesh::measure_quality(hexmesh::read_vtk_mesh(mesh_path));
    if (json) {
        std::cout << hexmesh::quality_json(report);
    } else {
        std::cout << fmt::format("quality of {}\n", mesh_path)
                  << hexmesh::format_quality_table(report);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"hexmesh: structured hexahedral grids for CFD from implicit bodies"};
    app.require_subcommand(1);

    std::string case_path, outdir = "out";
    bool keep_invalid = false;
    CLI::App* run_cmd = app.add_subcommand("run", "build the grid of a case file");
    run_cmd->add_option("case", case_path, "case file (JSON)")->required();
    run_cmd->add_option("-o,--output", outdir, "output directory")->capture_default_str();
    run_cmd->add_flag("--keep-invalid", keep_invalid,
                      "write a grid with inverted cells as grid_invalid.* instead of failing");

    std::string mesh_path;
    bool json = false;
    CLI::App* quality_cmd = app.add_subcommand("quality", "print the quality table of a mesh");
    quality_cmd->add_option("mesh", mesh_path, "hexahedral mesh (.vts .vtu .vtk .vtm)")->required();
    quality_cmd->add_flag("--json", json, "print the report as JSON");

    CLI11_PARSE(app, argc, argv);
    try {
        if (*run_cmd) return run(case_path, outdir, keep_invalid);
        if (*quality_cmd) return quality(mesh_path, json);
    } catch (const std::exception& e) {
        std::cerr << "hexmesh: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

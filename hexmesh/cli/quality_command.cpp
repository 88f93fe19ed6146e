// `hexmesh quality MESH [--json] [--surface CASE.json] [--case CASE.json]`: the quality table
// of a hexahedral or tetrahedral mesh file (a block grid measured against its case's body);
// `hexmesh report MESH [-o FILE] [--case CASE.json]`: its report page;
// `hexmesh compare A B [-o FILE]`: two such pages side by side.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/measure_file.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/tet_report.h"
#include "io/report_page.h"

namespace hexmesh::cli {
namespace {

struct Args {
    std::string mesh_path, surface, case_path;
    bool json = false;
};

void print_tet_quality(const Args& args, const TetMesh& mesh, const TetQualityReport& q) {
    std::optional<double> distance;
    if (!args.surface.empty()) distance = tet_boundary_distance(mesh, args.surface);
    if (args.json) {
        std::cout << tet_quality_json(q, distance);
        return;
    }
    std::cout << fmt::format("quality of {} ({} points)\n", args.mesh_path, q.points)
              << format_tet_quality_table({{"", &q, distance, std::nullopt, std::nullopt}});
}

}  // namespace

void add_quality_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("quality", "print the quality table of a mesh");
    cmd->add_option("mesh", args->mesh_path,
                    "hexahedral (.vts .vtu .vtk .vtm) or tetrahedral (.vtu .vtk) mesh")
        ->required();
    cmd->add_flag("--json", args->json, "print the report as JSON");
    cmd->add_option("--surface", args->surface,
                    "tet meshes: case file whose body the boundary should lie on (distance over "
                    "its wall cell size)");
    cmd->add_option("--case", args->case_path,
                    "block grids: the case whose body and wall law the wall is measured against "
                    "(default: grid.case.json beside the grid, if any)");
    cmd->callback([args, &exit_code] {
        if (const auto tets = read_tet_mesh(args->mesh_path)) {
            const TetQualityReport q = measure_tet_quality(*tets);
            print_tet_quality(*args, *tets, q);
            exit_code = q.inverted == 0 ? 0 : 3;
            return;
        }
        if (!args->surface.empty())
            throw std::invalid_argument("--surface is for tetrahedral meshes");
        const GridReport report = hex_file_report(args->mesh_path, args->case_path);
        if (args->json)
            std::cout << quality_json(report);
        else
            std::cout << fmt::format("quality of {}\n", args->mesh_path)
                      << format_quality_table(report);
        exit_code = 0;
    });
}

void add_report_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string mesh_path, output, case_path;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "report", "write the report page of a mesh: pictures, histograms, worst cells");
    cmd->add_option("mesh", args->mesh_path,
                    "block grid (.vtm .vts), hexahedral or tetrahedral mesh (.vtu .vtk)")
        ->required();
    cmd->add_option("-o,--output", args->output, "the page (default: report.html beside the mesh)");
    cmd->add_option("--case", args->case_path,
                    "block grids: the case whose body and wall law the wall is measured against "
                    "(default: grid.case.json beside the grid, if any)");
    cmd->callback([args, &exit_code] {
        ReportPage page = page_of_mesh(args->mesh_path, args->case_path);
        page.title = "hexmesh report " + page.title;
        page.peak_memory_bytes = peak_memory();
        std::cout << "written: "
                  << write_page(
                         args->output.empty()
                             ? std::filesystem::path(args->mesh_path).parent_path() / "report.html"
                             : std::filesystem::path(args->output),
                         report_page_html(page))
                  << "\n";
        exit_code = 0;
    });
}

void add_compare_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string a, b, output = "compare.html", case_a, case_b;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        app.add_subcommand("compare", "write the report pages of two meshes side by side");
    cmd->add_option("a", args->a, "first mesh (as for report)")->required();
    cmd->add_option("b", args->b, "second mesh")->required();
    cmd->add_option("-o,--output", args->output, "the page")->capture_default_str();
    cmd->add_option("--case-a", args->case_a,
                    "block grids: the first one's case (default: grid.case.json beside it)");
    cmd->add_option("--case-b", args->case_b, "the second one's");
    cmd->callback([args, &exit_code] {
        const ReportPage a = page_of_mesh(args->a, args->case_a),
                         b = page_of_mesh(args->b, args->case_b);
        std::cout << "written: " << write_page(args->output, compare_page_html(a, b)) << "\n";
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli

// `hexmesh quality MESH [--json] [--surface CASE.json] [--case CASE.json]`: the quality table
// of a hexahedral or tetrahedral mesh file (a block grid measured against its case's body);
// `hexmesh report MESH [-o FILE] [--case CASE.json]`: its report page;
// `hexmesh compare A B [-o FILE]`: two such pages side by side.
#include <fmt/format.h>

#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/run_case.h"
#include "hexmesh/pipeline/tet_mesh_case.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/tet_report.h"
#include "io/case_file.h"
#include "io/report_page.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"
#include "volume/grid_meter.h"

namespace hexmesh::cli {
namespace {

struct Args {
    std::string mesh_path, surface, case_path;
    bool json = false;
};

bool is_block_grid_file(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".vtm" || ext == ".vts";
}

// The case a block grid at `path` is measured against: `case_path`, else the grid.case.json
// `run` writes beside a grid, if any ("" for none).
std::string case_of_grid(const std::string& path, const std::string& case_path) {
    if (!case_path.empty()) return case_path;
    const std::filesystem::path beside =
        std::filesystem::path(path).parent_path() / "grid.case.json";
    return std::filesystem::exists(beside) ? beside.string() : std::string();
}

// The report of a block grid: measured against the body and wall law of the case file `sidecar`
// (case_of_grid; then also the wall's distance to a surface file, and follows_body), else ("")
// its cells alone. `settings` gets the case as JSON (empty without one).
GridReport block_grid_report(const BlockGrid& grid, const std::string& sidecar,
                             std::string& settings) {
    settings.clear();
    if (sidecar.empty()) {
        GridReport report;
        report.quality = measure_quality(grid);
        return report;
    }
    const Case c = read_case(sidecar);
    const Body body = make_body(c.geometry);
    const std::optional<TriangleSurface> surface = reference_surface(c.geometry);
    settings = case_to_json(c);
    return measure_grid(grid, *body, wall_layers(c), surface ? &*surface : nullptr);
}

// A file of tetrahedra only (legacy VTK or VTK XML unstructured), else nullopt.
std::optional<TetMesh> read_tet_mesh(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".vtu" && ext != ".vtk") return std::nullopt;
    VolumeMesh m = read_volume_mesh(path);
    if (m.num_tets() == 0 || m.num_hexes() > 0) return std::nullopt;
    return TetMesh{std::move(m.points), std::move(m.tets)};
}

void print_tet_quality(const Args& args, const TetMesh& mesh, const TetQualityReport& q) {
    std::optional<double> distance;
    if (!args.surface.empty()) {
        const Case c = read_case(args.surface);
        const Body body = make_body(c.geometry);
        const double h = tet_sizes(c, *body).wall;
        distance = max_boundary_distance(mesh, case_boundary(c, body, h)) / h;
    }
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
        GridReport report;
        const std::string sidecar = is_block_grid_file(args->mesh_path)
                                        ? case_of_grid(args->mesh_path, args->case_path)
                                        : std::string();
        if (!sidecar.empty()) {
            std::string settings;
            report = block_grid_report(read_vtk_block_grid(args->mesh_path), sidecar, settings);
        } else {
            if (!args->case_path.empty()) throw InputError("--case is for block grids (.vtm .vts)");
            const HexMesh mesh = read_vtk_mesh(args->mesh_path);
            report.quality = naming_file(args->mesh_path, [&] { return measure_quality(mesh); });
        }
        if (args->json)
            std::cout << quality_json(report);
        else
            std::cout << fmt::format("quality of {}\n", args->mesh_path)
                      << format_quality_table(report);
        exit_code = 0;
    });
}

namespace {

// The page of a block grid, measured as block_grid_report says.
ReportPage block_grid_page(const std::string& path, const std::string& case_path) {
    const BlockGrid grid = read_vtk_block_grid(path);
    std::string settings;
    const GridReport report = block_grid_report(grid, case_of_grid(path, case_path), settings);
    return grid_report_page(path, report, draw_grid(grid), settings);
}

// The page of any mesh file, titled by its path: a tet mesh, a block grid (see
// block_grid_page) or a hex mesh.
ReportPage page_of_mesh(const std::string& path, const std::string& case_path) {
    if (!std::filesystem::exists(path))
        throw InputError(fmt::format("{}: no such mesh file", path));
    if (const auto tets = read_tet_mesh(path))
        return tet_mesh_report_page(path, *tets, measure_tet_quality(*tets));
    if (is_block_grid_file(path)) return block_grid_page(path, case_path);
    if (!case_path.empty()) throw InputError("--case is for block grids (.vtm .vts)");
    const HexMesh mesh = read_vtk_mesh(path);
    return hex_mesh_report_page(path, mesh,
                                naming_file(path, [&] { return measure_quality(mesh); }));
}

}  // namespace

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

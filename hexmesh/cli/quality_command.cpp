// `hexmesh quality MESH [--json] [--surface CASE.json]`: the quality table of a hexahedral or
// tetrahedral mesh file.
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/tet_mesh_case.h"
#include "io/quality_report.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"

namespace hexmesh::cli {
namespace {

struct Args {
    std::string mesh_path, surface;
    bool json = false;
};

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
    cmd->add_option("mesh", args->mesh_path, "hexahedral (.vts .vtu .vtk .vtm) or tetrahedral (.vtu .vtk) mesh")
        ->required();
    cmd->add_flag("--json", args->json, "print the report as JSON");
    cmd->add_option("--surface", args->surface,
                    "tet meshes: case file whose body the boundary should lie on (distance over its wall cell size)");
    cmd->callback([args, &exit_code] {
        if (const auto tets = read_tet_mesh(args->mesh_path)) {
            const TetQualityReport q = measure_tet_quality(*tets);
            print_tet_quality(*args, *tets, q);
            exit_code = q.inverted == 0 ? 0 : 3;
            return;
        }
        if (!args->surface.empty()) throw std::invalid_argument("--surface is for tetrahedral meshes");
        GridReport report;
        const HexMesh mesh = read_vtk_mesh(args->mesh_path);
        report.quality = naming_file(args->mesh_path, [&] { return measure_quality(mesh); });
        if (args->json)
            std::cout << quality_json(report);
        else
            std::cout << fmt::format("quality of {}\n", args->mesh_path)
                      << format_quality_table(report);
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli

// `hexmesh quality MESH [--json]`: the quality table of any hexahedral mesh file.
#include <fmt/format.h>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "io/quality_report.h"
#include "io/vtk_mesh.h"

namespace hexmesh::cli {

void add_quality_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string mesh_path;
        bool json = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("quality", "print the quality table of a mesh");
    cmd->add_option("mesh", args->mesh_path, "hexahedral mesh (.vts .vtu .vtk .vtm)")->required();
    cmd->add_flag("--json", args->json, "print the report as JSON");
    cmd->callback([args, &exit_code] {
        GridReport report;
        report.quality = measure_quality(read_vtk_mesh(args->mesh_path));
        if (args->json)
            std::cout << quality_json(report);
        else
            std::cout << fmt::format("quality of {}\n", args->mesh_path)
                      << format_quality_table(report);
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli

// `hexmesh export GRID --format F -o OUT`: a block grid written in a CFD solver's format.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "io/case_file.h"
#include "io/export_grid.h"

namespace hexmesh::cli {

void add_export_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string grid_path, format, output, case_path;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("export", "write a block grid in a CFD format");
    cmd->add_option("grid", args->grid_path, "block grid (.vtm .vts from `run`, or Plot3D)")
        ->required();
    cmd->add_option("-f,--format", args->format, "one of: " + export_format_list())->required();
    cmd->add_option("-o,--output", args->output,
                    "output file (a case folder for openfoam; an existing case keeps its other "
                    "files)")
        ->required();
    cmd->add_option("--case", args->case_path,
                    "case file whose \"flow\" sets up the OpenFOAM case's fields (default: the "
                    "grid.case.json that `run` wrote beside the grid, if any)");
    cmd->callback([args, &exit_code] {
        if (!is_export_format(args->format))
            throw InputError(fmt::format("--format: unknown format '{}' (expected one of: {})",
                                         args->format, export_format_list()));
        FlowSpec flow;
        std::string flow_from = args->case_path;
        if (flow_from.empty()) {
            const std::filesystem::path beside =
                std::filesystem::path(args->grid_path).parent_path() / "grid.case.json";
            std::error_code ec;
            if (std::filesystem::is_regular_file(beside, ec)) flow_from = beside.string();
        }
        if (!flow_from.empty()) flow = read_case(flow_from).flow;
        const BlockGrid grid = read_block_grid(args->grid_path);
        if (args->format == "openfoam")
            std::cout << fmt::format(
                "flow: velocity ({}, {}, {}), density {}, viscosity {}, {} ({})\n",
                flow.velocity.x(), flow.velocity.y(), flow.velocity.z(), flow.density,
                flow.viscosity, flow.turbulence,
                flow_from.empty() ? "the defaults: no case file given or beside the grid"
                                  : "from " + flow_from);
        for (const std::string& f : naming_file(args->grid_path, [&] {
                 return export_grid(grid, args->format, args->output, flow);
             }))
            std::cout << fmt::format("written: {} ({} blocks, {} cells)\n", f, grid.blocks.size(),
                                     grid.num_cells());
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli

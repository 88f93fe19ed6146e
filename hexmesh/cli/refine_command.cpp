// `hexmesh refine GRID -o OUTDIR [--levels N] [--case CASE.json]`: a grid one (or N) levels finer,
// its last level made, measured and written block by block.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/measure_file.h"
#include "hexmesh/pipeline/ranks.h"
#include "hexmesh/pipeline/refine_grid_file.h"
#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"
#include "io/export_grid.h"

namespace hexmesh::cli {
namespace {

// The case of a grid: --case, else the grid.case.json `run` wrote beside it.
Case case_for_refining(const std::string& grid_path, const std::string& case_path) {
    const std::string path = case_of_grid(grid_path, case_path);
    if (path.empty())
        throw InputError(fmt::format(
            "{}: no case for this grid: give --case CASE.json (its geometry receives the new wall "
            "nodes) or keep the grid.case.json `run` writes beside the grid",
            grid_path));
    return read_case(path);
}

}  // namespace

void add_refine_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string grid_path, outdir, case_path;
        int levels = 1;
        bool no_report = false;
        std::vector<std::string> formats;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "refine", "split every cell of a block grid into 8 (nested: the old nodes stay put)");
    cmd->add_option("grid", args->grid_path, "block grid (.vtm or .vts from `run`)")->required();
    cmd->add_option("-o,--output", args->outdir, "output directory")->required();
    cmd->add_option("--levels", args->levels, "how many times to refine")
        ->check(CLI::Range(1, 4))
        ->capture_default_str();
    cmd->add_option("--case", args->case_path,
                    "case file of the grid (default: grid.case.json beside it)");
    cmd->add_option(
        "--format", args->formats,
        "also write the finest level in this format (repeatable): " + export_format_list() +
            " but vtk; under mpirun, openfoam is a decomposed case (processor0 "
            ".. processorN-1) and the others are gathered at the first process");
    cmd->add_flag("--no-report", args->no_report,
                  "do not write report.html (pictures, histograms, worst cells)");
    cmd->callback([args, &exit_code] {
        // Under mpirun every process checks its input: if one cannot read it, all stop.
        Case c;
        ranks::together([&] {
            if (!std::filesystem::exists(args->grid_path))
                throw InputError(fmt::format("{}: no such grid file", args->grid_path));
            for (const std::string& f : args->formats)
                if (f == "vtk" || !is_export_format(f))
                    throw InputError(fmt::format(
                        "--format {}: {}", f,
                        f == "vtk" ? "the grid is always written as VTK (grid.vtm)"
                                   : "unknown format (expected one of: " + export_format_list() +
                                         " but vtk)"));
            c = case_for_refining(args->grid_path, args->case_path);
        });
        // Under mpirun, rank 0 speaks for every process.
        std::ostringstream quiet;
        std::ostream& out = ranks::rank() == 0 ? std::cout : quiet;
        out << fmt::format("hexmesh refine {}{}\n", args->grid_path,
                           ranks::size() > 1 ? fmt::format(" ({} processes)", ranks::size()) : "");
        RefineFileOptions options;
        options.levels = args->levels;
        options.report = !args->no_report;
        options.formats = args->formats;
        const RefineFileResult result =
            refine_grid_file(args->grid_path, c, args->outdir, options, out);
        for (const std::string& f : result.files) out << "written: " << f << "\n";
        // As in run: a refined grid whose wall misses part of the body, or folds across its
        // surface, is written with a warning, and cells over checkMesh's aspect-ratio limit get
        // a note.
        const std::string warning = ranks::rank() == 0 ? body_missed_warning(result.report) +
                                                             through_wall_warning(result.report)
                                                       : "";
        out << warning << (ranks::rank() == 0 ? aspect_ratio_note(result.report.quality) : "");
        exit_code = warning.empty() ? 0 : 3;
    });
}

}  // namespace hexmesh::cli

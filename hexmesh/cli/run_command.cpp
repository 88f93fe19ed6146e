// `hexmesh run CASE.json -o OUTDIR`: the grid of a case file.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/pipeline/run_case.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/case_file.h"

namespace hexmesh::cli {

void add_run_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string case_path, outdir = "out";
        bool keep_invalid = false, no_report = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("run", "build the grid of a case file");
    cmd->add_option("case", args->case_path, "case file (JSON)")->required();
    cmd->add_option("-o,--output", args->outdir, "output directory")->capture_default_str();
    cmd->add_flag("--keep-invalid", args->keep_invalid,
                  "write a grid with inverted cells as grid_invalid.* instead of failing");
    cmd->add_flag("--no-report", args->no_report,
                  "do not write report.html (pictures, histograms, worst cells)");
    cmd->callback([args, &exit_code] {
        const Case c = read_case(args->case_path);
        std::cout << fmt::format("hexmesh run {}\n", args->case_path);
        RunOptions options;
        options.keep_invalid = args->keep_invalid;
        options.report = !args->no_report;
        const RunResult result = run_case(c, args->outdir, options, std::cout);
        std::cout << "\n" << format_quality_table(result.report) << "\n";
        if (!result.level_reports.empty()) {
            std::vector<FamilyLevel> table;
            for (size_t l = 0; l < result.level_reports.size(); ++l)
                table.push_back(family_level(int(l) + 1, result.level_reports[l]));
            std::cout << "grid-convergence family (refinement ratio 2; the table above is the "
                         "finest level):\n"
                      << format_family_table(table) << "\n";
        }
        for (const std::string& f : result.files) std::cout << "written: " << f << "\n";
        // A grid that misses part of the body, or folds across its surface, is written, with a
        // warning (per level of a family) and exit code 3.
        bool follows = true;
        const size_t levels = std::max<size_t>(result.level_reports.size(), 1);
        for (size_t l = 0; l < levels; ++l) {
            const GridReport& level =
                result.level_reports.empty() ? result.report : result.level_reports[l];
            const std::string prefix = levels > 1 ? fmt::format("level {}: ", l + 1) : "";
            const std::string warning =
                body_missed_warning(level, prefix) + through_wall_warning(level, prefix);
            follows = follows && warning.empty();
            std::cout << warning;
        }
        std::cout << aspect_ratio_note(result.report.quality);
        exit_code = result.report.quality.solver_valid() && follows ? 0 : 3;
    });
}

}  // namespace hexmesh::cli

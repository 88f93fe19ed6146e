// `hexmesh refine GRID -o OUTDIR [--levels N] [--case CASE.json]`: a grid one (or N) levels finer,
// its last level made, measured and written block by block.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/refine_family.h"
#include "hexmesh/pipeline/run_case.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "io/case_file.h"
#include "io/report_page.h"
#include "io/staged_output.h"
#include "io/vtk_mesh.h"
#include "volume/grid_meter.h"

namespace hexmesh::cli {
namespace {

// The case of a grid: --case, else the grid.case.json `run` wrote beside it.
Case case_of_grid(const std::string& grid_path, const std::string& case_path) {
    if (!case_path.empty()) return read_case(case_path);
    const std::filesystem::path sidecar =
        std::filesystem::path(grid_path).parent_path() / "grid.case.json";
    if (!std::filesystem::exists(sidecar))
        throw InputError(fmt::format(
            "{}: no case for this grid: give --case CASE.json (its geometry receives the new wall "
            "nodes) or keep the grid.case.json `run` writes beside the grid",
            grid_path));
    return read_case(sidecar.string());
}

}  // namespace

void add_refine_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string grid_path, outdir, case_path;
        int levels = 1;
        bool no_report = false;
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
    cmd->add_flag("--no-report", args->no_report,
                  "do not write report.html (pictures, histograms, worst cells)");
    cmd->callback([args, &exit_code] {
        if (!std::filesystem::exists(args->grid_path))
            throw InputError(fmt::format("{}: no such grid file", args->grid_path));
        const Case c = case_of_grid(args->grid_path, args->case_path);
        std::cout << fmt::format("hexmesh refine {}\n", args->grid_path);
        PhaseTimer timer(std::cout);
        StagedOutput out(args->outdir);  // locked from the start: a second run into it is refused
        BlockGrid grid = read_vtk_block_grid(args->grid_path);
        timer.done("read",
                   fmt::format("({} blocks, {} cells)", grid.blocks.size(), grid.num_cells()));
        const Body body = make_body(c.geometry);
        timer.done("geometry");
        // Every level but the last in memory (each is 8 times smaller than the next); the
        // last one block by block: each fine block is measured, written and dropped.
        for (int level = 1; level < args->levels; ++level) {
            RefinementResult r = refine_on_body(grid, *body);
            grid = std::move(r.grid);
            timer.done("refine", fmt::format("({} cells, {} wall nodes projected, max move {:.3g})",
                                             grid.num_cells(), r.projected, r.max_projection));
        }
        const std::optional<TriangleSurface> surface = reference_surface(c.geometry);
        GridMeter meter(*body, {}, surface ? &*surface : nullptr);
        VtkGridWriter writer(out.path(grid.blocks.size() == 1 ? "grid.vts" : "grid.vtm"),
                             grid.blocks.size());
        // The last level's pictures, drawn block by block too (framed on the level before).
        std::optional<GridPictures> pictures;
        if (!args->no_report) pictures.emplace(grid_pictures_for(grid));
        std::vector<double> values;
        double refine_s = 0, quality_s = 0, write_s = 0;
        auto lap = [clock = std::chrono::steady_clock::now()]() mutable {
            const auto now = std::chrono::steady_clock::now();
            const double s = std::chrono::duration<double>(now - clock).count();
            clock = now;
            return s;
        };
        const RefinementStats stats = refine_blocks(grid, *body, {}, [&](RefinedBlock& piece) {
            const Block& block = piece.grid.blocks[0];
            const double r = lap();
            meter.add(piece.grid, block, &piece.ids);
            if (pictures) {
                values.resize(std::size_t(block.cells().count()));
                scaled_jacobians(piece.grid, block, values.data());
                pictures->add_block(piece.grid, block, values.data());
            }
            const double q = lap();
            writer.add(piece.grid, block);
            const double w = lap();
            refine_s += r;
            quality_s += q;
            write_s += w;
            std::cout << fmt::format(
                "    block {:<12} {:>11} cells: refine {:.2f} s, quality {:.2f} s, write {:.2f} "
                "s\n",
                block.name, block.cells().count(), r, q, w);
        });
        writer.finish();
        write_s += lap();
        const GridReport report = meter.report();
        quality_s += lap();
        timer.done(
            "refine",
            fmt::format("({} cells, {} wall nodes projected, max move {:.3g}; block by block: "
                        "refine {:.2f} s, quality {:.2f} s, write {:.2f} s)",
                        report.quality.cells, stats.projected, stats.max_projection, refine_s,
                        quality_s, write_s));
        std::cout << "\n" << format_quality_table(report) << "\n";
        if (report.quality.inverted_cells > 0)
            throw std::runtime_error(
                fmt::format("{}: the refined grid has {} inverted cells; "
                            "nothing written",
                            args->grid_path, report.quality.inverted_cells));
        out.write_text("quality.json", quality_json(report));
        out.write_text("grid.case.json", case_to_json(c));
        if (pictures) {
            ReportPage page = grid_report_page("hexmesh refine " + args->grid_path, report,
                                               pictures->pictures(), case_to_json(c));
            page.phase_seconds = timer.phases();
            page.peak_memory_bytes = peak_memory();
            out.write_text("report.html", report_page_html(page));
        }
        const std::vector<std::string> written = out.commit();
        timer.done("write");
        for (const std::string& f : written) std::cout << "written: " << f << "\n";
        // As in run: a refined grid whose wall misses part of the body is written with a warning.
        const std::string warning = body_missed_warning(report);
        std::cout << warning;
        exit_code = warning.empty() ? 0 : 3;
    });
}

}  // namespace hexmesh::cli

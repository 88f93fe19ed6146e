#include "hexmesh/pipeline/refine_grid_file.h"

#include <fmt/format.h>

#include <optional>

#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_meter.h"
#include "hexmesh/quality/grid_report.h"
#include "io/report_page.h"
#include "io/staged_output.h"
#include "io/vtk_mesh.h"

namespace hexmesh {
namespace {

// The last level made block by block: each fine block measured by `meter`, drawn into
// `pictures` (if any) and written by `writer` as it comes, one log line per block. Adds the
// time spent in each to `seconds` (refine, quality, write).
RefinementStats refine_last_level(const BlockGrid& grid, const ImplicitFunction& body,
                                  GridMeter& meter, std::optional<GridPictures>& pictures,
                                  VtkGridWriter& writer, Lap& lap, double (&seconds)[3],
                                  std::ostream& log) {
    std::vector<double> values;
    return refine_blocks(grid, body, {}, [&](RefinedBlock& piece) {
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
        seconds[0] += r;
        seconds[1] += q;
        seconds[2] += w;
        log << fmt::format(
            "    block {:<12} {:>11} cells: refine {:.2f} s, quality {:.2f} s, write {:.2f} "
            "s\n",
            block.name, block.cells().count(), r, q, w);
    });
}

}  // namespace

RefineFileResult refine_grid_file(const std::string& grid_path, const Case& c,
                                  const std::string& outdir, const RefineFileOptions& options,
                                  std::ostream& log) {
    PhaseTimer timer(log);
    StagedOutput out(outdir);  // locked from the start: a second run into it is refused
    BlockGrid grid = read_vtk_block_grid(grid_path);
    timer.done("read", fmt::format("({} blocks, {} cells)", grid.blocks.size(), grid.num_cells()));
    const Body body = make_body(c.geometry);
    timer.done("geometry");
    // Every level but the last in memory (each is 8 times smaller than the next); the
    // last one block by block: each fine block is measured, written and dropped.
    for (int level = 1; level < options.levels; ++level) {
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
    if (options.report) pictures.emplace(grid_pictures_for(grid));
    Lap lap;
    double seconds[3] = {0, 0, 0};  // refine, quality, write
    const RefinementStats stats =
        refine_last_level(grid, *body, meter, pictures, writer, lap, seconds, log);
    writer.finish();
    seconds[2] += lap();
    RefineFileResult result;
    result.report = meter.report();
    seconds[1] += lap();
    timer.done("refine", fmt::format("({} cells, {} wall nodes projected, max move {:.3g}; block "
                                     "by block: refine {:.2f} s, quality {:.2f} s, write {:.2f} s)",
                                     result.report.quality.cells, stats.projected,
                                     stats.max_projection, seconds[0], seconds[1], seconds[2]));
    log << "\n" << format_quality_table(result.report) << "\n";
    if (result.report.quality.inverted_cells > 0)
        throw std::runtime_error(
            fmt::format("{}: the refined grid has {} inverted cells; "
                        "nothing written",
                        grid_path, result.report.quality.inverted_cells));
    out.write_text("quality.json", quality_json(result.report));
    out.write_text("grid.case.json", case_to_json(c));
    if (pictures) {
        ReportPage page = grid_report_page("hexmesh refine " + grid_path, result.report,
                                           pictures->pictures(), case_to_json(c));
        page.phase_seconds = timer.phases();
        page.peak_memory_bytes = peak_memory();
        out.write_text("report.html", report_page_html(page));
    }
    result.files = out.commit();
    timer.done("write");
    return result;
}

}  // namespace hexmesh

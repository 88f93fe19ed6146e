#include "hexmesh/pipeline/refine_grid_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>

#include "hexmesh/core/bytes.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/phase_timer.h"
#include "hexmesh/pipeline/ranks.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/pipeline/refined_outputs.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_meter.h"
#include "hexmesh/quality/grid_report.h"
#include "io/input_error.h"
#include "io/report_page.h"
#include "io/staged_output.h"
#include "io/vtk_mesh.h"

namespace hexmesh {
namespace {

// What refine_last_level measured and drew of the blocks it made, and their times.
struct LastLevel {
    RefinementStats stats;
    double seconds[3] = {0, 0, 0};  // refine, quality, write
};

// The last level made block by block, this process's share of `pieces` (every block whole
// with one process): each piece measured by `meter` (its cells numbered as in the whole
// grid), drawn into `pictures` (if any) and written by `writer` as piece p as it comes, one
// log line per piece; kept in `kept` when given (for other formats), else dropped. A block
// split between processes is made whole by each of them, each keeping its part.
LastLevel refine_last_level(const BlockGrid& grid, const ImplicitFunction& body,
                            const std::vector<BlockPiece>& pieces, GridMeter& meter,
                            std::optional<GridPictures>& pictures, const VtkGridWriter& writer,
                            MadeBlocks* kept, std::ostream& log) {
    const int rank = ranks::rank();
    std::vector<Id> first_cell(grid.blocks.size(), 0);  // of each fine block
    for (size_t b = 1; b < grid.blocks.size(); ++b)
        first_cell[b] = first_cell[b - 1] + 8 * grid.blocks[b - 1].cells().count();
    std::vector<bool> made(grid.blocks.size(), false);
    for (const BlockPiece& p : pieces) made[p.block] = made[p.block] || p.process == rank;
    LastLevel out;
    std::vector<double> values;
    size_t b = 0;  // the block coming
    Lap lap;
    out.stats = refine_blocks(
        grid, body, {},
        [&](RefinedBlock& fine) {
            while (!made[b]) ++b;
            const double r = lap();
            out.seconds[0] += r;
            for (size_t p = 0; p < pieces.size(); ++p) {
                const BlockPiece& at = pieces[p];
                if (at.block != b || at.process != rank) continue;
                const bool whole = at.lo == 0 && at.hi == fine.grid.blocks[0].cells()[at.axis];
                RefinedBlock part = whole ? RefinedBlock{} : part_of(fine, at.axis, at.lo, at.hi);
                RefinedBlock& piece = whole ? fine : part;
                const Block& block = piece.grid.blocks[0];
                CellNumbering numbering{first_cell[b], {0, 0, 0}, fine.grid.blocks[0].cells()};
                numbering.offset[size_t(at.axis)] = at.lo;
                meter.add(piece.grid, block, &piece.ids, numbering);
                if (pictures) {
                    if (ranks::size() > 1) pictures->set_order(std::uint32_t(p));
                    values.resize(std::size_t(block.cells().count()));
                    scaled_jacobians(piece.grid, block, values.data());
                    pictures->add_block(piece.grid, block, values.data());
                }
                const double q = lap();
                writer.add_piece(p, piece.grid, block);
                const double w = lap();
                out.seconds[1] += q;
                out.seconds[2] += w;
                log << fmt::format(
                    "    block {:<12} {:>11} cells: refine {:.2f} s, quality {:.2f} s, write "
                    "{:.2f} s{}\n",
                    block.name, block.cells().count(), r, q, w,
                    whole ? ""
                          : fmt::format(" (cells {} to {} along {})", at.lo, at.hi - 1,
                                        "ijk"[at.axis]));
                log.flush();
                if (kept) {
                    kept->index.push_back(p);
                    kept->blocks.push_back(std::move(piece));
                }
            }
            ++b;
        },
        &made);
    out.seconds[0] += lap();  // the blocks skipped
    return out;
}

// The last level's blocks made by each process: its own blocks, made and written; then
// every process's measures and pictures merged into rank 0's, with their log lines and
// times.
void gather_measures(GridMeter& meter, std::optional<GridPictures>& pictures, LastLevel& level,
                     const std::string& lines, std::ostream& log) {
    ByteWriter mine;
    ranks::together([&] {
        mine.put(meter.pack());
        mine.put(pictures ? pictures->pack() : std::string());
        mine.put(lines);
        mine.put(level.stats.polished);
        mine.put(double(peak_memory()));
    });
    const std::vector<std::string> all = ranks::gather(mine.bytes());
    ranks::together([&] {
        double peak = 0;
        for (size_t r = 0; r < all.size(); ++r) {
            ByteReader in(all[r]);
            const std::string packed_meter = in.next<std::string>();
            const std::string packed_pictures = in.next<std::string>();
            const std::string rank_lines = in.next<std::string>();
            const Id polished = in.next<Id>();
            peak = std::max(peak, in.next<double>());
            if (r == 0) continue;
            meter.merge(packed_meter);
            if (pictures) pictures->merge(packed_pictures);
            level.stats.polished += polished;
            log << fmt::format("  process {}:{}", r,
                               rank_lines.empty() ? " no block (more processes than blocks)\n"
                                                  : "\n" + rank_lines);
        }
        if (all.size() > 1)
            log << fmt::format("  {} processes, the largest peak memory {:.2f} GB\n", all.size(),
                               peak / 1e9);
    });
}

// A decomposed OpenFOAM case needs a piece per process: a block is cut no finer than two
// coarse cells along an index direction (share_blocks).
void refuse_idle_processors(const std::vector<std::string>& formats, int processes, size_t pieces) {
    if (processes > 1 && size_t(processes) > pieces &&
        std::count(formats.begin(), formats.end(), "openfoam"))
        throw InputError(fmt::format(
            "--format openfoam on {} processes: the grid's blocks make {} pieces at most (a "
            "piece has two coarse cells along the direction it is cut in at least), one per "
            "process: run on at most {} processes",
            processes, pieces, pieces));
}

// At rank 0, every measure merged: the level's report, its log line and table; throws when
// the level has cells a solver refuses (QualityReport::solver_valid; nothing is written then).
GridReport report_level(const GridMeter& meter, const LastLevel& level,
                        const std::string& grid_path, PhaseTimer& timer, std::ostream& log) {
    GridReport report = meter.report();
    const double* seconds = level.seconds;
    timer.done("refine",
               fmt::format("({} cells, {} wall nodes projected, max move {:.3g}; block "
                           "by block: refine {:.2f} s, quality {:.2f} s, write {:.2f} s)",
                           report.quality.cells, level.stats.projected, level.stats.max_projection,
                           seconds[0], seconds[1], seconds[2]));
    log << "\n" << format_quality_table(report) << "\n";
    if (!report.quality.solver_valid())
        throw std::runtime_error(fmt::format("{}: the refined grid has {}; nothing written",
                                             grid_path, invalid_cells(report.quality)));
    return report;
}

// quality.json, grid.case.json and report.html (with pictures) into `out`, then the output
// moved into place; returns its files.
std::vector<std::string> write_summary(StagedOutput& out, const Case& c, const std::string& title,
                                       const GridReport& report,
                                       const std::optional<GridPictures>& pictures,
                                       PhaseTimer& timer) {
    out.write_text("quality.json", quality_json(report));
    out.write_text("grid.case.json", case_to_json(c));
    if (pictures) {
        ReportPage page = grid_report_page(title, report, pictures->pictures(), case_to_json(c));
        page.phase_seconds = timer.phases();
        page.peak_memory_bytes = peak_memory();
        out.write_text("report.html", report_page_html(page));
    }
    std::vector<std::string> files = out.commit();
    timer.done("write");
    return files;
}

}  // namespace

RefineFileResult refine_grid_file(const std::string& grid_path, const Case& c,
                                  const std::string& outdir, const RefineFileOptions& options,
                                  std::ostream& log) {
    const int rank = ranks::rank(), processes = ranks::size();
    PhaseTimer timer(log);
    // Rank 0 holds the output folder (locked from the start: a second run into it is
    // refused); every process writes its blocks into its staging folder.
    std::optional<StagedOutput> out;
    std::string staging;
    ranks::together([&] {
        if (rank == 0) {
            out.emplace(outdir);
            staging = out->staging_folder();
        }
    });
    staging = ranks::broadcast(staging);
    // Every process reads the grid and the geometry and makes the levels before the last.
    BlockGrid grid;
    Body body;
    std::optional<TriangleSurface> surface;
    std::optional<GridMeter> meter;
    std::optional<GridPictures> pictures;
    std::vector<BlockPiece> pieces;
    ranks::together([&] {
        grid = read_vtk_block_grid(grid_path);
        timer.done("read",
                   fmt::format("({} blocks, {} cells)", grid.blocks.size(), grid.num_cells()));
        body = make_body(c.geometry);
        timer.done("geometry");
        // Every level but the last in memory (each is 8 times smaller than the next); the
        // last one block by block: each fine block is measured, written and dropped.
        for (int level = 1; level < options.levels; ++level) {
            RefinementResult r = refine_on_body(grid, *body);
            grid = std::move(r.grid);
            timer.done("refine", fmt::format("({} cells, {} wall nodes projected, max move {:.3g})",
                                             grid.num_cells(), r.projected, r.max_projection));
        }
        surface = reference_surface(c.geometry);
        meter.emplace(*body, WallLayers{}, surface ? &*surface : nullptr);
        // The last level's pictures, drawn block by block too (framed on the level before).
        if (options.report) pictures.emplace(grid_pictures_for(grid));
        pieces = share_blocks(grid, processes);
        refuse_idle_processors(options.formats, processes, pieces.size());
    });
    const std::string vtk_name = pieces.size() == 1 ? "grid.vts" : "grid.vtm";
    std::ostringstream rank_lines;  // the block lines of the other processes, for rank 0
    LastLevel level;
    std::optional<VtkGridWriter> writer;
    MadeBlocks kept;
    ranks::together([&] {
        writer.emplace((std::filesystem::path(staging) / vtk_name).string(), pieces.size());
        level = refine_last_level(grid, *body, pieces, *meter, pictures, *writer,
                                  options.formats.empty() ? nullptr : &kept,
                                  rank == 0 ? log : rank_lines);
    });
    gather_measures(*meter, pictures, level, rank_lines.str(), log);
    // Rank 0 has every measure now: the report, and the refusal of a level a solver refuses
    // before any other format is written.
    RefineFileResult result;
    ranks::together([&] {
        if (rank == 0) result.report = report_level(*meter, level, grid_path, timer, log);
    });
    const std::vector<std::string> formats_written =
        write_refined_formats(grid, pieces, kept, options.formats, staging, c.flow);
    if (!options.formats.empty())
        timer.done("formats", fmt::format("({})", fmt::join(options.formats, ", ")));
    ranks::together([&] {
        if (rank != 0) return;
        std::vector<std::string> names;
        for (const BlockPiece& p : pieces) names.push_back(grid.blocks[p.block].name);
        out->path(vtk_name);  // written below, or by add_piece for a grid of one block
        writer->write_index(names);
        for (const std::string& name : formats_written) out->path(name);
        result.files =
            write_summary(*out, c, "hexmesh refine " + grid_path, result.report, pictures, timer);
    });
    return result;
}

}  // namespace hexmesh

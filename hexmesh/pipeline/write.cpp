#include "hexmesh/pipeline/write.h"

#include <fmt/format.h>

#include <filesystem>

#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/measure.h"
#include "hexmesh/pipeline/refine.h"
#include "io/export_grid.h"
#include "io/report_page.h"
#include "io/vtk_mesh.h"

namespace hexmesh {
namespace {

// Writes one grid, its quality.json, grid.case.json and report.html into `out` under `dir`
// ("" or "level_2/"), refusing a grid with inverted cells unless keep_invalid.
void write_level(Job& job, const BlockGrid& grid, GridReport report, const std::string& dir,
                 StagedOutput& out) {
    const Case& c = job.settings;
    refuse_invalid(job, report, dir);
    const std::string stem = dir + (report.quality.solver_valid() ? "grid" : "grid_invalid");
    const std::string file = out.path(stem + (grid.blocks.size() == 1 ? ".vts" : ".vtm"));
    std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    write_vtk_grid(grid, file);
    for (const std::string& format : c.outputs)  // the VTK grid above is always written
        if (format != "vtk")
            write_grid_format(
                grid, format,
                out.path(dir + export_file_name(format, stem.substr(dir.size()), grid)), c.flow);
    const std::string level = dir.empty() ? "" : " " + dir.substr(0, dir.size() - 1);
    job.timer.done("write" + level);
    report.phase_seconds = job.timer.phases();
    report.peak_memory_bytes = peak_memory();
    out.write_text(dir + "quality.json", quality_json(report));
    out.write_text(dir + "grid.case.json", case_to_json(c));
    if (!job.options.report) return;
    ReportPage page =
        grid_report_page(fmt::format("hexmesh run {}{}", c.path, dir.empty() ? "" : "," + level),
                         report, draw_grid(grid), case_to_json(c));
    page.peak_memory_bytes = peak_memory();
    out.write_text(dir + "report.html", report_page_html(page));
    job.timer.done("report" + level);
}

}  // namespace

std::vector<std::string> write_grids(Job& job, StagedOutput& out) {
    if (job.levels.size() == 1) {
        write_level(job, job.levels[0], job.reports[0], "", out);
        return out.commit();
    }
    std::vector<FamilyLevel> table;
    for (int level = 1; level <= int(job.levels.size()); ++level) {
        const std::string dir = fmt::format("level_{}/", level);
        write_level(job, job.levels[level - 1], job.reports[level - 1], dir, out);
        table.push_back(family_level(level, job.reports[level - 1]));
    }
    out.write_text("family.json", family_json(table));
    return out.commit();
}

}  // namespace hexmesh

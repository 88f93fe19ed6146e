#include "hexmesh/pipeline/measure.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <stdexcept>
#include <vector>

#include "hexmesh/pipeline/build_blocks.h"
#include "hexmesh/pipeline/refine.h"
#include "hexmesh/quality/grid_meter.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/wall_metrics.h"

namespace hexmesh {

std::string invalid_cells(const QualityReport& q) {
    if (q.inverted_cells > 0) return fmt::format("{} inverted cells", q.inverted_cells);
    std::vector<std::string> what;
    if (q.negative_pyramids > 0)
        what.push_back(fmt::format("{} face pyramids of negative volume", q.negative_pyramids));
    if (q.faces_over_90_deg > 0)
        what.push_back(fmt::format("{} faces at 90 degrees of non-orthogonality or more",
                                   q.faces_over_90_deg));
    if (q.nonpositive_volumes > 0)
        what.push_back(fmt::format("{} cells of volume <= 0", q.nonpositive_volumes));
    if (q.highly_skewed_faces > 0)
        what.push_back(fmt::format("{} faces of skewness over 4", q.highly_skewed_faces));
    return fmt::format("cells that a finite-volume solver refuses: {}", fmt::join(what, ", "));
}

GridReport measure_level(const Job& job, int level) {
    const WallLayers law = refined_wall_layers(wall_layers(job.settings), level);
    return measure_grid(job.levels[level - 1], *job.body, law,
                        job.surface ? &*job.surface : nullptr);
}

void measure(Job& job) {
    job.reports = {measure_level(job, 1)};
    if (job.reports[0].wall) job.reports[0].wall->surface_in_cells_by_stage = job.wall_misses;
    job.timer.done("quality");
}

void note_wall_miss(Job& job, const std::string& stage) {
    if (!job.surface) return;
    try {
        const HausdorffDistance d = surface_to_wall_in_cells(job.grid(), *job.surface);
        job.wall_misses.push_back({stage, d.surface_in_cells_max, d.surface_in_cells_p99});
    } catch (const std::invalid_argument&) {
        // No wall quad of non-zero area at this stage: nothing to note (the run goes on).
    }
}

void refuse_invalid(const Job& job, const GridReport& report, const std::string& dir) {
    if (report.quality.solver_valid() || job.options.keep_invalid) return;
    const Vec3& at = report.quality.worst_cell_centre;
    const std::optional<CellPlace>& w = report.worst_cell;
    throw std::runtime_error(job.naming_hole(fmt::format(
        "{}: the grid {}has {} (min scaled Jacobian {:.3g} at ({:.4g}, {:.4g}, {:.4g}){}); "
        "nothing written (use --keep-invalid to write it as grid_invalid.*)",
        job.settings.path, dir.empty() ? "" : "of " + dir.substr(0, dir.size() - 1) + " ",
        invalid_cells(report.quality), report.quality.min_scaled_jacobian, at.x(), at.y(), at.z(),
        w ? fmt::format(", block {} cell ({}, {}, {}){}", w->block, w->i, w->j, w->k,
                        w->on_wall ? " on the wall" : "")
          : "")));
}

}  // namespace hexmesh

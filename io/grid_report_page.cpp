// The report page of a block grid: its summary, histograms and worst cells from its quality
// report, and its pictures (wall views and cuts coloured by scaled Jacobian).
#include <fmt/format.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/wall_quality.h"
#include "io/report_page.h"

namespace hexmesh {

ReportPage grid_report_page(const std::string& title, const GridReport& report,
                            std::vector<Picture> pictures, const std::string& settings_json) {
    const QualityReport& q = report.quality;
    ReportPage page;
    page.title = title;
    page.summary = fmt::format(
        "{} cells: <span class=\"{}\">{}</span>; min scaled Jacobian {:.4g}, mean {:.4g}.", q.cells,
        q.solver_valid() ? "good" : "bad",
        q.solver_valid()
            ? "valid"
            : fmt::format("not valid for a solver ({} inverted cells, {} face pyramids "
                          "of negative volume, {} faces at 90 degrees or more, {} faces of "
                          "skewness over 4)",
                          q.inverted_cells, q.negative_pyramids, q.faces_over_90_deg,
                          q.highly_skewed_faces),
        q.min_scaled_jacobian, q.mean_scaled_jacobian);
    if (const std::string missed = body_missed(report); !missed.empty())
        page.summary += fmt::format(" <span class=\"bad\">Not the body's grid: {}.</span>", missed);
    if (const std::string folded = through_wall(report); !folded.empty())
        page.summary += fmt::format(" <span class=\"bad\">{}.</span>", folded);
    page.value_lo = 0;  // under 0 (inverted) gets its own colour
    page.value_hi = 1;
    page.pictures = std::move(pictures);
    page.histograms.push_back(
        {"scaled_jacobian", "Scaled Jacobian of the cells", "scaled Jacobian",
         q.scaled_jacobian_histogram,
         fmt::format("{} cells; 1 is a cube, 0 or less a cell folded at a corner", q.cells)});
    page.histograms.push_back(
        {"non_orthogonality", "Non-orthogonality of the internal faces",
         "degrees (OpenFOAM's definition)", q.non_orthogonality_histogram,
         fmt::format("{} internal faces; solvers refuse 90 degrees or more ({} here)",
                     q.internal_faces, q.faces_over_90_deg)});
    if (report.wall) {
        const WallQuality& w = *report.wall;
        if (w.first_layer_target > 0)
            page.histograms.push_back(
                {"first_layer", "First-layer height over its target", "height / target",
                 w.first_layer_histogram,
                 fmt::format(
                     "{} wall cells, target {:.4g}; {:.1f} % within 10 % (the bins 0.9 and 1.0)",
                     w.wall_cells, w.first_layer_target, 100 * w.first_layer_within_10_percent)});
        if (w.growth_ratios > 0)
            page.histograms.push_back(
                {"growth_ratio",
                 w.growth_ratio_target > 0 ? "Growth ratio over its target"
                                           : "Growth ratio along the wall-normal lines",
                 w.growth_ratio_target > 0 ? "ratio / target" : "ratio", w.growth_ratio_histogram,
                 w.growth_ratio_target > 0
                     ? fmt::format(
                           "{} ratios in the boundary layer, target {:.4g}; {:.1f} % within 5 %",
                           w.growth_ratios, w.growth_ratio_target,
                           100 * w.growth_ratio_within_5_percent)
                     : fmt::format("{} ratios", w.growth_ratios)});
    }
    for (std::size_t r = 0; r < q.worst_cells.size(); ++r) {
        const RankedCell& c = q.worst_cells[r];
        ReportCell cell{c.scaled_jacobian, fmt::format("cell {}", c.cell), c.centre, false};
        if (r < report.worst_places.size() && !report.worst_places[r].block.empty()) {
            const CellPlace& p = report.worst_places[r];
            cell.where = fmt::format("block {} ({}, {}, {}){}", p.block, p.i, p.j, p.k,
                                     p.on_wall ? ", on the wall" : "");
            cell.on_wall = p.on_wall;
        }
        page.worst.push_back(cell);
    }
    page.quality_table = format_quality_table(report);
    page.quality_json = quality_json(report);
    page.settings_json = settings_json;
    page.phase_seconds = report.phase_seconds;
    return page;
}

GridPictures grid_pictures_for(const BlockGrid& grid) {
    std::vector<Vec3> wall;  // the nodes of the faces whose patch is "wall"
    for (const Block& block : grid.blocks)
        for (int f = 0; f < 6; ++f) {
            if (block.face_patch[f] != "wall") continue;
            const Dims n = block.nodes;
            const int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::array<int, 3> at;
            at[axis] = f % 2 ? n[axis] - 1 : 0;
            for (at[v] = 0; at[v] < n[v]; ++at[v])
                for (at[u] = 0; at[u] < n[u]; ++at[u])
                    wall.push_back(grid.points[block.node_ids[n.flat(at[0], at[1], at[2])]]);
        }
    const Box3 domain = bounds_of(grid.points);
    return GridPictures(wall.empty() ? domain : bounds_of(wall), domain, 0, 1);
}

std::vector<Picture> draw_grid(const BlockGrid& grid) {
    GridPictures pictures = grid_pictures_for(grid);
    bool has_wall = false;
    for (const Block& block : grid.blocks)
        for (const std::string& patch : block.face_patch) has_wall = has_wall || patch == "wall";
    std::vector<double> values;
    for (const Block& block : grid.blocks) {
        values.resize(std::size_t(block.cells().count()));
        scaled_jacobians(grid, block, values.data());
        pictures.add_block(grid, block, values.data(), !has_wall);
    }
    return pictures.pictures();
}

}  // namespace hexmesh

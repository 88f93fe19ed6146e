// Boundary-layer and surface-fidelity metrics of a grid's wall
// (docs/architecture.md#quality-metrics), as plain data.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hexmesh/core/histogram.h"
#include "hexmesh/core/types.h"

namespace hexmesh {

// Measured along the wall-normal lines of the grid (hexmesh/quality/wall_metrics.h measures them):
// one line per node of every block face whose patch is "wall", going into the block. Lengths are in
// geometry units, fractions in [0, 1]. A target of 0 means "no law given": its fraction is then 0
// and means nothing.
struct WallQuality {
    Id wall_cells = 0;  // cells with a face on a wall patch, counted once per block face

    // First-layer thickness of a wall cell: mean over its 4 wall nodes of the first edge of
    // the line projected on the unit wall normal there pointing into the grid (> 0 when
    // valid); at a crease or corner node, the normal of the piece the cell lies on (the one
    // nearest its wall face's normal), so the layer laid along the bisector there measures
    // its height above that face.
    double first_layer_min = 0;
    double first_layer_mean = 0;
    double first_layer_max = 0;
    double first_layer_target = 0;             // the law's first height
    double first_layer_within_10_percent = 0;  // fraction of wall cells within 10 % of target
    // Wall cells whose first-layer thickness is <= 0: the cell lies through the wall, on the
    // body's side of its own wall face (inside the body for an exterior grid, outside it for an
    // interior one), every corner tet possibly positive. Where the thinnest wall cell is: the
    // centre of its wall face.
    Id cells_through_wall = 0;
    Vec3 first_layer_min_at = Vec3::Zero();

    // Growth ratio spacing(m+1) / spacing(m), spacing(m) = |x(m+1) - x(m)| along a line, over the
    // boundary-layer edges (m = 0 .. layers-2), or over the whole line without a law.
    Id growth_ratios = 0;  // number of ratios measured; the statistics are 0 when none
    double growth_ratio_min = 0;
    double growth_ratio_mean = 0;
    double growth_ratio_max = 0;
    double growth_ratio_target = 0;            // the law's growth ratio
    double growth_ratio_within_5_percent = 0;  // fraction of ratios within 5 % of target

    // Angle between the first edge of each line and the wall normal, degrees (0 = ideal); at a
    // crease or corner, the bisector of the faces meeting there.
    double orthogonality_max_deg = 0;
    double orthogonality_mean_deg = 0;

    // For grids of a surface file: the two one-sided distances (grid wall nodes to the
    // surface, surface samples to the grid's wall faces) and their maximum.
    std::optional<double> hausdorff;
    std::optional<double> grid_to_surface;
    std::optional<double> surface_to_grid;
    // Every surface vertex's distance to the wall in sizes of the wall quad nearest to it
    // (square root of its area): max and 99th percentile.
    std::optional<double> surface_in_cells_max;
    std::optional<double> surface_in_cells_p99;
    // The surface vertex of that max, and its distance to the wall.
    std::optional<Vec3> surface_in_cells_at;
    std::optional<double> surface_in_cells_distance;
    // The same max and 99th percentile for the wall at the stages of the run that made the
    // grid, in order ("as placed", "after the surface pass" unless there is none, "after the
    // volume passes"; the polish is in the figures above): where the wall left the body. Empty
    // when not recorded (a grid read from a file, a refined level).
    struct Stage {
        std::string name;
        double max = 0, p99 = 0;
    };
    std::vector<Stage> surface_in_cells_by_stage;

    // Every wall cell's first-layer thickness over the target, 20 bins over [0, 2) (empty
    // without a target: bins 9 and 10 hold the cells within 10 %); every growth ratio over its
    // target, 20 bins over [0.8, 1.2) (without a target, the ratio itself over [0.5, 2.5)).
    Histogram first_layer_histogram;
    Histogram growth_ratio_histogram;
};

}  // namespace hexmesh

// The `run` stage untangle_and_optimize: the joint untangling and optimization of a block grid
// on its body (the variational step), the boundary layer laid again (lay_boundary_layer.h), and
// the worst cells polished in their neighbourhood.
#pragma once

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/corner_tets.h"
#include "hexmesh/pipeline/job.h"
#include "untangle/untangle.h"
#include "volume/stretching.h"

namespace hexmesh {

struct GridOptimizationOptions {
    untangle::UntangleOptions untangle;  // solvers per phase, theta, iteration budgets, log
    // The boundary layer the grid must keep. With layers > 0, after the joint optimization the
    // layer nodes are laid again along the optimized wall's normals (volume/wall_extrusion.h)
    // and the grid around them (relax_rings) is optimized once more, wall and layers held (kept
    // only if every cell is then valid). Also when the joint optimization left inverted
    // elements, all at the wall or its layers: the layers laid along the normals can free them
    // (the bull outside: 2 left by the joint pass, none after this one), so the joint pass
    // leaves such elements to it when its untangling first stalls, instead of going on by the
    // safe rule and trying its last resorts (UntangleOptions::leave_to_next_pass). Not when one
    // lies away from them (GridOptimizationResult::layers_skipped): on every run measured that pass
    // freed none of those (bench/RESULTS.md), and the grid is refused as the joint pass left it.
    WallLayers wall_layers;
    // The nodes beyond the laid layers follow them over this many nodes along each line, and
    // the pass after the layers are laid again optimizes the cells within this many cell
    // rings of the laid nodes and of the cells with a scaled Jacobian below relax_below once
    // the layers are laid; the rest of the grid keeps the joint pass's positions. 0: the nodes
    // beyond follow to the line's far end and the whole grid is optimized again.
    int relax_rings = 8;
    double relax_below = 0.5;
    // Nodes that must not move whatever their kind (sized like grid.points, or empty for
    // none), e.g. the coarse nodes of a refined grid, which keep a family nested. Cells whose
    // 8 nodes are all held are left out of the functional.
    std::vector<bool> held;
    // Cells with a layer node (or the first node beyond the layers) of a wall-normal line from
    // a crease or corner of the body (the laid layers' cells and the two beyond) take their own
    // initial shape as target instead of a box, unless a corner of that shape has a scaled
    // Jacobian under 0.2 (a cell a crease cuts across): for grids built with those lines along
    // the faces' bisector and the layers on the faces' offset planes (the exterior O-grid,
    // volume/o_grid.h), whose cells there fan out and are not boxes.
    bool keep_crease_shapes = false;
    // Both passes hold the wall quads to the body with this weight (hold_wall_quads).
    double wall_fidelity = 0;
    // When > 0, the joint pass's local repair tries at most this many neighbourhood sizes and
    // leaves what stays inverted to the next pass (UntangleOptions::local_rounds): for a grid
    // that is made again another way when it stays tangled.
    int local_rounds = 0;
};

struct GridOptimizationResult {
    untangle::UntangleResult solve;        // the joint optimization
    untangle::UntangleResult layers_held;  // the pass after the layers were laid again
    // Whether the grid keeps the laid layers: false when that pass could not make every cell
    // valid, and the joint optimization's grid was kept instead.
    bool layers_laid = false;
    // Some attempt of that pass found inverted elements to untangle (layers_held is the last's).
    bool layers_untangled = false;
    // Cells of the laid layers that came out inverted with every node held (laid, or held
    // beyond the relaxed rings): that pass was then skipped.
    Id layers_blocked = 0;
    // Wall lines whose laid cells would have crossed (an inverted corner tet of laid nodes
    // only): given back the joint optimization's nodes, their layers as it left them.
    Id lines_given_back = 0;
    // Wall and layer nodes the law placed; 0 when no wall-normal line could be laid alone
    // (volume/wall_extrusion.h) and the second pass was skipped, or when layers_skipped.
    Id laid_nodes = 0;
    // The joint optimization left an inverted element away from the wall and its layers, so
    // the layers were not laid again.
    bool layers_skipped = false;
    // The work (untangle::UntangleResult::work) of every untangling of both passes.
    double untangling_work = 0;
};

// Splits every hex of `grid` into its 8 corner tets and minimizes the functional
// (docs/architecture.md#the-functional) over the grid's points (updated in place). Each cell's
// target is the box of its own initial edge lengths along i, j and k (mean of the 4 parallel
// edges), so the boundary-layer cells the grid was built with (thin in the wall-normal direction)
// stay thin while their angles are driven towards 90 degrees; with keep_crease_shapes, the cells
// along crease lines keep their initial shapes as targets. Nodes move according to grid.kinds: slip
// nodes slide on u = 0 of `body` (tangent plane of grad u, then the projection V), feature_edge
// nodes slide along the body's crease through them (surface/implicit_features.h), corner and fixed
// nodes stay.
// Never returns a grid worse than its input (fewer inverted corner tets, then lower energy).
// A work budget in options.untangle (max_work) bounds both passes' untangling together.
GridOptimizationResult optimize_grid(BlockGrid& grid, const ImplicitFunction& body,
                                     const GridOptimizationOptions& options);

struct PolishOptions {
    untangle::UntangleOptions untangle;
    double below =
        0.3;         // cells whose scaled Jacobian (Verdict's, centre frame included) is under this
    int rings = 2;   // and the cells within this many rings of them are optimized again
    int rounds = 4;  // at most this many times
    // Instead of the cells under `below`, those a solver refuses (find_refused_cells).
    bool refused_only = false;
    std::vector<bool> held;    // as in GridOptimizationOptions
    double wall_fidelity = 0;  // as in GridOptimizationOptions
};

struct PolishResult {
    Id cells = 0, cells_after = 0;  // cells polished (under `below`, or refused) before and after
    // Inverted cells plus checkMesh's failures (QualityReport::solver_valid), before and after.
    Id refused_before = 0, refused_after = 0;
    double min_sj_before = 0, min_sj_after = 0;
    int rounds = 0;
    double seconds = 0;
};

// The worst cells of an optimized grid optimized again in their neighbourhood, the rest held:
// a global optimization stops when the mean energy no longer falls, while a few cells (thin
// parts of the body, wall quads bent round a fold) are still poor, and in a small problem
// they weigh. Targets: each cell's box of its current edge lengths. Each round starts from the
// one before; the grid returned is the best seen (fewer cells a solver refuses, then a
// higher worst scaled Jacobian, then fewer cells under `below`), never worse than the input.
PolishResult polish_worst_cells(BlockGrid& grid, const ImplicitFunction& body,
                                const PolishOptions& options);

// The stage on job.grid(): optimize_grid with the case's solver and boundary-layer law (the
// exterior's crease cells keep their shapes), then, unless some cell is still inverted,
// polish_worst_cells with the wall and its layers held, and what a solver still refuses
// mended node by node (mend_cells.h) and polished again with the layers free, and last the
// worst cells lifted node by node (lift_worst_cells), the layers' nodes on their levels of u.
// Logs one summary per pass; notes how far the wall misses a surface file after optimize_grid
// (note_wall_miss).
void untangle_and_optimize(Job& job);

}  // namespace hexmesh

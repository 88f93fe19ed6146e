// Cells a finite-volume solver refuses though every corner tet is positive (a face warped past
// its cell's centre, a face too skewed), mended by moving their own nodes one at a time.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

struct MendOptions {
    int rounds = 40;           // sweeps over the nodes, per ring
    int rings = 2;             // the refused cells' nodes, then those of the cells around them
    double enough = 0.05;      // a node whose cells' solver margin is over this is left alone
    double first_step = 0.25;  // trial moves: this share of the mean edge at the node, halved
    double last_step = 1e-3;   // down to this share
    std::vector<bool> held;    // nodes that do not move (sized like grid.points, or empty)
};

struct MendResult {
    Id refused_before = 0, refused_after = 0;            // find_refused_cells, whole grid
    Id moves = 0;                                        // trial moves kept
    double min_margin_before = 0, min_margin_after = 0;  // over the refused cells' neighbourhood
};

// The cells find_refused_cells names (hexmesh/quality/mesh_quality.h), mended: each node of theirs
// (interior or slip; slip nodes projected back onto u = 0 of `body`) tries six moves along the axes
// and keeps the best for the cells around it: fewer refused cells (solver_margin <= 0), then fewer
// of their faces of skewness over max_solver_skewness, then a higher smallest margin (a skewed
// face's being its relative excess, negative), so a cell the solver accepts is never traded away
// (not even for a skewed face) and with as many refused the smallest margin there never falls; the
// step halved when none helps. When that leaves refused cells, the nodes of the cells sharing a
// node with them join in. The functional's corner tets do not see a face pyramid on the cell's
// centre; this sees exactly what the solver checks. Deterministic; the grid's points are changed
// in place.
MendResult mend_refused_cells(BlockGrid& grid, const ImplicitFunction& body,
                              const MendOptions& options = {});

}  // namespace hexmesh

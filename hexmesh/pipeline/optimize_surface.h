// The surface pass of `run`: the wall grid alone on u = 0 with the 2D functional.
#pragma once

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "untangle/untangle.h"

namespace hexmesh {

struct SurfaceOptimizationResult {
    untangle::UntangleResult solve;  // inverted = folded triangles (against grad u)
    Id nodes = 0, triangles = 0;     // wall nodes and their corner triangles
    double max_move = 0;             // largest wall-node displacement, in mean wall edges
};

// Optimizes the grid on u = 0 (the nodes of the blocks' "wall" faces) alone with the 2D
// functional of DESIGN §4 (untangle/triangle_energy.h), measured in the tangent plane of
// grad u (DESIGN §7: surface grid first, then the volume). Every wall quad gives its 4
// corner triangles, each with the target of a rectangle corner with the quad's mean edge
// lengths as given, so the cells keep their sizes while their corners are driven towards
// right angles and folds on the surface are untangled. Slip nodes slide on u = 0,
// feature_edge nodes along their crease, corner and fixed nodes stay. Only wall nodes move:
// the caller builds the volume again from them (build_grid's wall_from) or carries it along
// (carry_interior_tfi). Never leaves the wall grid worse than given (fewer folded
// triangles, then lower energy).
SurfaceOptimizationResult optimize_wall_surface(BlockGrid& grid, const ImplicitFunction& body,
                                                const untangle::UntangleOptions& options);

}  // namespace hexmesh

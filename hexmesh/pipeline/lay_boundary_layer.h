// lay_boundary_layer, part of the untangle_and_optimize stage (run by its optimize_grid): after
// the joint untangling and optimization, the boundary layer laid again along the optimized
// wall's normals by the case's law (volume/wall_extrusion.h), and the grid around it optimized
// once more, wall and layers held.
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/untangle_and_optimize.h"

namespace hexmesh {

// Whether some corner tet of `grid` is inverted with none of its nodes on the wall or its
// `layers` layers: laying the layers again is then skipped
// (GridOptimizationResult::layers_skipped).
bool inverted_away_from_layers(const BlockGrid& grid, int layers);

// The layer pass of optimize_grid on the grid the joint pass left (see
// GridOptimizationOptions::wall_layers): the layer nodes laid by options.wall_layers, the
// layers, the cells below options.relax_below and the cells up to options.relax_rings rings
// around both optimized again towards the targets of `initial` (the grid as given; `shaped`
// as in corner_tet_problem), the rest held. Lines whose laid cells cross are given back to the
// joint result first; when the pass still leaves inverted cells, or cells under half the
// joint result's worst scaled Jacobian (the first run ending at its untangling's first stall
// when every element still inverted has a laid node), the lines through them are given back
// too and it runs once more; then the better valid result is kept, else the joint one. Fills
// result's layers_held, layers_laid, layers_blocked, lines_given_back and laid_nodes.
void lay_boundary_layer(BlockGrid& grid, const ImplicitFunction& body,
                        const GridOptimizationOptions& options, const std::vector<Vec3>& initial,
                        const std::vector<bool>& shaped, GridOptimizationResult& result);

}  // namespace hexmesh

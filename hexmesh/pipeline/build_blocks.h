// The first `run` stage, build_blocks: the body read from the case, the route its wall grid takes
// (rays from a centre, or the sphere map of a body that is not star-shaped), the case's open
// choices resolved, and the initial block grid (interior O-H or single block, exterior O-grid).
#pragma once

#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/job.h"
#include "hexmesh/pipeline/wall_route.h"
#include "io/case_file.h"
#include "volume/o_h_grid.h"
#include "volume/stretching.h"

namespace hexmesh {

// Reads job.settings' body (refusing a surface of several bodies or with handles), chooses
// its wall route, resolves the exterior's wall cells, the centre, grid.axis "auto"
// (choose_o_h_axis) and the default core size (core_size_within_wall) in job.settings, and
// builds job.levels = {the initial grid}. Throws InputError when the body cannot be gridded
// so, naming why.
void build_blocks(Job& job);

// The initial grid of the case's body, before any optimization: interior O-H or single
// block, or the exterior O-grid out to the far field. Throws InputError when a cell_size
// asks for an absurd number of cells. With `wall_from` (the points of a grid build_grid made
// for the same case, its wall grid since moved on u = 0), the O-H and O-grid lines are built
// from those wall nodes instead of the radial projections; the single block has no such
// construction and throws std::invalid_argument. grid.axis "auto" is resolved by
// choose_o_h_axis (volume/o_h_grid.h) on each call.
// With a route that is not radial (a body that is not star-shaped: hexmesh/pipeline/wall_route.h),
// the route's wall lattice (or wall_from's) instead of the radial projections, and for the
// exterior its lines up the route's potential.
BlockGrid build_grid(const Case& c, const ImplicitFunction& body,
                     const std::vector<Vec3>* wall_from = nullptr,
                     const WallRoute* route = nullptr);

// The O-H grid options of an interior case (grid.axis "auto" as -1: see choose_o_h_axis).
OHGridOptions o_h_grid_options(const Case& c, const ImplicitFunction& body);

// The boundary-layer law of the case (layers = 0 without a boundary_layer block).
WallLayers wall_layers(const Case& c);

}  // namespace hexmesh

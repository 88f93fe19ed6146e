// The `run` stage surface_grid: the wall grid on u = 0 before the volume — wall nodes snapped
// to the body's creases and corners, then optimized alone with the 2D functional, and the volume
// built again from them.
#pragma once

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/job.h"
#include "untangle/untangle.h"

namespace hexmesh {

struct SurfaceOptimizationResult {
    untangle::UntangleResult solve;  // inverted = folded triangles (against grad u)
    Id nodes = 0, triangles = 0;     // wall nodes and their corner triangles
    double max_move = 0;             // largest wall-node displacement, in mean wall edges
};

// Optimizes the grid on u = 0 (the nodes of the blocks' "wall" faces) alone with the 2D
// functional (docs/architecture.md#the-functional) (untangle/triangle_energy.h), measured in the
// tangent plane of grad u (docs/architecture.md#construction: surface grid first, then the volume).
// Every wall quad gives its 4 corner triangles, each with the target of a rectangle corner with the
// quad's mean edge lengths as given, so the cells keep their sizes while their corners are driven
// towards right angles and folds on the surface are untangled. Slip nodes slide on u = 0,
// feature_edge nodes along their crease, corner and fixed nodes stay. Only wall nodes move:
// the caller builds the volume again from them (build_grid's wall_from) or carries it along
// (carry_interior_tfi). With fidelity > 0 every quad is also held to the body between its
// nodes (untangle::HeldQuad; a quad whose centre lies a wall cell off u = 0 costs fidelity
// times its best shape energy), so that nodes do not leave a limb's tip or a fin's edge to
// the quads bridging it. Never leaves the wall grid worse than given (fewer folded
// triangles, then lower energy).
SurfaceOptimizationResult optimize_wall_surface(BlockGrid& grid, const ImplicitFunction& body,
                                                const untangle::UntangleOptions& options,
                                                double fidelity = 0);

// The stage on job.grid(): with a radial route, wall nodes snapped onto the body's creases and
// corners (volume/feature_snapping.h; a wall placed through the sphere map follows no crease,
// and nodes pulled across its lines would fold its quads). Then, unless the case's
// solver.surface_iterations is 0, optimize_wall_surface, and the volume from the optimized
// wall: the O-H and O-grid lines built again (build_grid's wall_from), a single block's
// interior carried along by TFI. When the volume built so has more cells with a scaled
// Jacobian <= 0 than the grid had, or cannot be built (wall nodes that slid far from their
// lines' core or far-field ends, in deep concavities), the grid as constructed is kept. How far
// the wall misses a surface file is noted before and after (note_wall_miss).
void make_surface_grid(Job& job);

}  // namespace hexmesh

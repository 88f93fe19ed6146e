// An exterior grid's lines carried out as the trajectory of the wall grid: where neighbouring
// gradient lines part or merge, their nodes are spread out again on the potential's levels.
#pragma once

#include "hexmesh/core/implicit_function.h"
#include "untangle/untangle.h"
#include "volume/wall_paths.h"

namespace hexmesh {

// What spread_on_levels did: levels visited, levels where quads were spread out, levels where
// quads to repair were left as they were (no repair made them all sound), lines moved.
struct LevelSpreading {
    int levels = 0, levels_spread = 0, levels_left = 0;
    Id lines_moved = 0;
};

// Walks `paths` (gradient lines of `potential` from the wall lattice, CubeSurfaceLattice
// numbering, n cells per patch edge, up to paths.far_level) level by level, from the level a
// typical line reaches in its first step (a quarter of a wall edge: below it, about a boundary
// layer, the lines stay the gradient lines) up to the far level, about 15 % higher each time.
// On each level the lattice's quads are checked:
// a quad folded or squeezed (a corner angle under 6 degrees, as where two lines meet) or
// three times wider or narrower than a neighbour (where two lines part round a finger) is
// repaired with the 2D functional, its nodes within two rings (four, eight if it stays
// folded) sliding on that level (the rest held), each quad's target a square of the size
// its neighbourhood has. A repair is kept only when it leaves none of its quads folded or
// squeezed (on a level with handles, between two saddle values of the potential, a sliding
// repair may not exist). A moved node's line goes on from there up the gradient, so the next
// level starts from the repaired one: the grid's lines follow the gradient wherever the wall
// grid carried out by it stays sound, and are the wall grid's continuation elsewhere.
LevelSpreading spread_on_levels(const ImplicitFunction& potential, WallPaths& paths,
                                const untangle::UntangleOptions& solver);

}  // namespace hexmesh

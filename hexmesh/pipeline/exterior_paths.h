// The lines of an exterior grid round a body that is not star-shaped: from its wall nodes out
// through the levels of its exterior potential (along its gradient, or along the fibres of a
// field of directions) to a level that is star-shaped.
#pragma once

#include <vector>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/spread_on_levels.h"
#include "surface/exterior_potential.h"
#include "untangle/untangle.h"
#include "volume/wall_paths.h"

namespace hexmesh {

// The gradient line of `potential` from p up to the level F = c0 (the midpoint rule at unit
// speed, points `step` apart, the last one on the level), and F at its points in `levels`
// (non-decreasing). It ends early where the gradient vanishes or after 4 bounds diagonals of
// steps.
// With `climb_pockets`, where the gradient vanishes or the line has not risen above its highest
// point for 4 steps (a pocket of the interpolant: in gaps about as narrow as the potential's
// lattice, F is near its solve's noise), it climbs instead: to the highest point higher than
// that on the nearest ring of 64 directions at 1, 2, 4 or 8 steps that has one (the last point
// bisected onto the level); it then ends early only where no ring has one. Such a step does
// not follow the gradient: a line that climbed may cross its neighbours', or jump across a
// part of the body thinner than 2 steps.
std::vector<Vec3> gradient_line_up(const ImplicitFunction& potential, Vec3 p, double c0,
                                   double step, std::vector<double>& levels,
                                   bool climb_pockets = false);

// The paths of an exterior grid's lines (volume/wall_paths.h) from the wall lattice `wall`
// (CubeSurfaceLattice numbering, n cells per patch edge) up `potential` (F = 0 on the body,
// rising away from it without a local maximum: surface/exterior_potential.h) to its level c0,
// which must be star-shaped around `centre`; points every quarter of a wall edge; a line that
// stops short is traced again climbing out of pockets. Gradient lines never cross, so the
// lines of neighbouring wall nodes stay neighbours out to that level. Their far-field
// directions: from the centre to the paths' ends, the lattice's quads on the unit sphere then
// untangled and smoothed with the 2D functional (each quad's target the rectangle of its own
// mean edge lengths; `solver`'s methods), so that a fold the lines carry out (from the wall, or
// where gradient lines pass a saddle of the potential, as between the legs of an animal) is not
// fixed in the far field. Throws std::invalid_argument, naming the wall point, when a line
// stops short of c0 even so (no higher point near where it stops), std::runtime_error when a
// line leaves no finite point. With `spread`, the lines are first carried out level by level
// and repaired where they part or fold (hexmesh/pipeline/spread_on_levels.h), what was done
// stored there. With `theta`, each line instead runs a wall edge up the gradient and then
// along its fibre of theta (direction_line_up; up the gradient as above where the fibre stops
// short of c0): fibres do not part at the potential's saddles.
WallPaths exterior_paths(const ImplicitFunction& potential, const std::vector<Vec3>& wall,
                         double c0, int cells_per_edge, const Vec3& centre,
                         const untangle::UntangleOptions& solver, LevelSpreading* spread = nullptr,
                         const HarmonicDirections* theta = nullptr);

// The fibre {theta / |theta| = d} of `theta` (d its direction at the line's start) from p up to
// the level F = c0 of `potential`, after a first stretch of length `along_gradient` up its
// gradient; points `step` apart (predictor-corrector), F at them in `levels` (its running
// maximum). Ends early where the fibre's tangent vanishes or it meets the fibre of -d.
std::vector<Vec3> direction_line_up(const ImplicitFunction& potential,
                                    const HarmonicDirections& theta, Vec3 p, double c0, double step,
                                    double along_gradient, std::vector<double>& levels);

// The paths of an interior grid's lines (volume/wall_paths.h) from the wall lattice `wall` up
// the body's interior potential (0 on the body, rising in to 1 on a ball round `centre`:
// surface/exterior_potential.h) to its level c0, star-shaped around `centre`; points every
// quarter of a wall edge. A line that stops short of c0 even climbing out of pockets (in a
// long limb the potential decays below its solve's noise) is left as its wall point alone: its
// grid line runs straight from the wall. No far-field directions.
WallPaths interior_paths(const ImplicitFunction& potential, const std::vector<Vec3>& wall,
                         double c0, int cells_per_edge, const Vec3& centre);

}  // namespace hexmesh

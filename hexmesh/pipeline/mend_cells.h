// Cells a finite-volume solver refuses though every corner tet is positive (a face warped past
// its cell's centre, a face too skewed), mended, and the worst cells of a grid lifted, by
// moving nodes one at a time.
#pragma once

#include <optional>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "surface/analytic.h"
#include "volume/stretching.h"

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
// and keeps the best for the cells around it: fewer inverted cells (a corner tet of exact
// orientation <= 0) and inverted corner tets, then fewer refused cells (solver_margin <= 0), then
// fewer of their faces of skewness over max_solver_skewness, then a higher smallest margin (a
// skewed face's being its relative excess, negative), so a valid cell is never traded for fewer
// refused ones, a cell the solver accepts is never traded away (not even for a skewed face) and
// with as many refused the smallest margin there never falls; the
// step halved when none helps. When that leaves refused cells, the nodes of the cells sharing a
// node with them join in. The functional's corner tets do not see a face pyramid on the cell's
// centre; this sees exactly what the solver checks. Deterministic; the grid's points are changed
// in place.
MendResult mend_refused_cells(BlockGrid& grid, const ImplicitFunction& body,
                              const MendOptions& options = {});

struct LiftOptions {
    double below = 0.3;          // the cells whose scaled Jacobian is under this are lifted
    int rings = 1;               // with the nodes of this many rings of cells around them
    int rounds = 60;             // sweeps over the nodes
    double first_step = 0.1;     // trial moves: this share of the mean edge at the node, halved
    double last_step = 1e-3;     // down to this share
    std::vector<bool> on_level;  // interior nodes that keep their value of u (the wall's layers)
    std::vector<bool> held;      // nodes that do not move (sized like grid.points, or empty)
    // Wall-normal lines (a wall node, then its layers' nodes outwards), also moved whole.
    std::vector<std::vector<Id>> lines;
    bool ascent = true;  // the max-min steepest ascent's moves (see lift_worst_cells)
    // The far field's surface (u = 0 of it) and its nodes (sized like grid.points), which slide
    // on it though their kind is fixed; nullptr: they stay.
    const ImplicitFunction* far = nullptr;
    std::vector<bool> on_far;
    int joint_iterations = 200;  // steps of the worst cells' nodes moved together, at most
};

struct LiftResult {
    Id cells_before = 0, cells_after = 0;        // cells under `below`, whole grid
    double min_sj_before = 0, min_sj_after = 0;  // worst scaled Jacobian, whole grid
    Id moves = 0;                                // trial moves kept
    Id line_moves = 0;                           // of which moves of whole lines
    Id joint_steps = 0;                          // steps of the worst cells' nodes together
};

// The worst scaled Jacobian of a grid raised node by node, in sweeps: each node of a cell under
// `below` that is interior, slip or on a crease tries small moves (along the level set of u
// through it: a slip node's u = 0, a node of `on_level` its own value, so a boundary layer keeps
// its heights above the wall where u is a distance; a crease node's along its crease; any other
// interior node's along the axes) and takes, of those that raise the smallest scaled Jacobian
// of its cells, the best ranked by it whose Score (mend_refused_cells) is better than before:
// no more cells a solver refuses around it, then no more faces over the skewness limit. The
// step is halved when none helps. The nodes of `rings` rings of cells around them join in once
// a cell of theirs falls under `below` (a move raises the worst cell around its node and may
// lower another). Each line of `lines` with a node there whose wall node is slip and whose other
// nodes are of `on_level` also tries, in each sweep, to move whole (every node by the same
// tangent offset, each onto its own level) or sheared (node t of T by t / T of it): a line that
// leaves the wall leaning, which a node moved alone cannot straighten. With `ascent`, a node
// (not on a crease) or a line none of whose moves helps also tries the max-min steepest ascent
// of the frames of its cells (the 9 whose minimum is a cell's scaled Jacobian; Freitag and
// Plassmann's direction: the point nearest the origin of the convex hull of the gradients of
// the nearly smallest), as far as its step or to where, to first order, another frame meets
// the smallest, and half that; and after the sweeps the worst cells of the whole grid are
// raised by moving their nodes together (up to `joint_iterations` steps of the same ascent in
// all their moves at once, the solver margins of the cells around held from falling to 0):
// where each node is at a max-min point of its own cells, the worst cell is still raised by
// several moving together. The nodes of `on_far` slide on `far` as the wall's on u = 0 (the
// far layer's cells are no better than the far field's quads). Corner nodes stay. Where the
// joint optimization's functional weighs every cell, this weighs only the worst one around each
// node: the shear of a boundary layer bent round a crease, which the polish holds. Deterministic;
// the grid's worst scaled Jacobian never falls; the grid's points are changed in place.
LiftResult lift_worst_cells(BlockGrid& grid, const ImplicitFunction& body,
                            const LiftOptions& options = {});

struct LayerHeightsResult {
    Id lines = 0;  // wall lines whose layer nodes lie off the law's heights
    Id moved = 0;  // of which moved (the whole way, or part of it)
    Id within_before = 0, within_after = 0;  // their first-layer heights within 10 % of the law's
};

// The boundary layer's heights restored on the wall lines that lie off them: the lines the
// layer pass gave back to the joint optimization (their laid cells crossed or fell low) keep
// the joint's layer nodes, wherever its functional put them (the spool outside: first heights
// from -0.6 to 7 times the law's on 200 of 2402 lines), and the lift moves lines whole. On each
// line, nodes m = 1 .. M (M as layers_that_fit gives for the line) go to x0 + d_m s, x0 its wall
// node and d_m the law's heights: on a smooth wall s is the ray through node M scaled to be 1
// above the wall (the line's lean kept: each node's own offset along the wall would shear the
// cells of a thinner layer); at a crease or corner, the step 1 above every piece meeting there
// (unit_offset, as the layers were laid). The next M nodes move by node M's displacement
// decreasing linearly; the line's far end stays. A line lies off when some node m is off its
// height above a piece by more than 5 % of its layer's thickness. A move is taken when the
// cells around the moved nodes keep their Score (no more inverted cells or corner tets, cells a
// solver refuses or skewed faces) and none of them falls below the grid's worst scaled Jacobian
// (or below its own value, if lower): the grid's worst never falls. (A floor of 0.3 instead
// held back a third of the spool's lines, over cells of 0.30-0.37 that the lift had raised to
// there: 92.2 % of its wall within 10 % with it, 93.5 % without, mean scaled Jacobian 0.8813
// and 0.8816.) Else half the move is tried. Up to 8 sweeps, until one moves no line: lines side
// by side off their heights, each of which would shear its neighbour's cells if moved alone,
// come down together. Wall nodes stay, and so do lines that share a node with another (a
// single block walled on several sides). Deterministic; the grid's points are changed in place.
// law.layers == 0 leaves the grid as it is.
LayerHeightsResult restore_layer_heights(BlockGrid& grid, const ImplicitFunction& body,
                                         const WallLayers& law);

// The sphere through the nodes of the grid's "farfield" faces (an exterior O-grid's far field),
// with those nodes marked in `on_far` (sized like grid.points): LiftOptions' far and on_far.
// nullopt, and `on_far` empty, when there are fewer than 4 or they do not lie on one sphere to
// 1e-9 of its radius (a far-field box).
std::optional<Sphere> far_field_sphere(const BlockGrid& grid, std::vector<bool>& on_far);

}  // namespace hexmesh

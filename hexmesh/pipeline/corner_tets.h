// corner_tets, part of the untangle_and_optimize stage (and of the polish and of refine): the
// untangling problem of a block grid. Every hex is split into its 8 corner tets
// (core/reference_hex.h: hex_corner_tets) with targets from the grid, and the boundary nodes
// get the body's geometry through one adapter (boundary_geometry.h): slip on u = 0, feature
// edges along its creases. Also the node sets the passes hold or free.
#pragma once

#include <array>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "untangle/problem.h"

namespace hexmesh {

// The functional over the cells that have a node free to move (`held` empty: every cell):
// its points are the grid nodes `nodes` (local -> grid id; empty: all grid nodes, same ids),
// the nodes of those cells only, so a refined grid whose new wall nodes alone are free
// costs memory for them, not for the whole grid.
struct GridProblem {
    untangle::Problem problem;
    std::vector<Id> nodes;
    Id grid_id(Id local) const { return nodes.empty() ? local : nodes[local]; }
    // The solved positions back into the grid.
    void scatter(std::vector<Vec3>& points) const {
        if (nodes.empty())
            points = problem.points;
        else
            for (size_t i = 0; i < nodes.size(); ++i) points[nodes[i]] = problem.points[i];
    }
    // Whether every element inverted at `x` (the problem's points) has a node `marked` (by
    // grid id): e.g. all at the wall and its layers, which a later pass can free.
    bool inverted_all_touch(const std::vector<Vec3>& x, const std::vector<bool>& marked) const;
};

// The problem of the cells that have a node not `held` (empty: every cell), each cell's 8
// corner tets with the box of its mean edge lengths along i, j, k in `target_points` (node
// positions of the grid) as target; the cells with a `shaped` node (empty: none) target their
// own shapes there, unless a corner of that shape has a scaled Jacobian under 0.2 (a cell a
// crease cuts across). Held nodes are fixed; the others move as grid.kinds say (slide_on).
GridProblem corner_tet_problem(const BlockGrid& grid, const std::vector<Vec3>& target_points,
                               const ImplicitFunction& body, const std::vector<bool>& held,
                               const std::vector<bool>& shaped);

// Holds the wall to the body between its nodes (untangle::HeldQuad): every wall quad of
// `grid` whose 4 nodes are in g's problem, one of them free to move, gets the term
// fidelity (4/3) V (u(c) / h)^2, with c the quad's centre, V the volume of its cell's target
// box in `target_points` and h^2 the box's wall area: a quad one wall cell off the body costs
// `fidelity` times its cell's best shape energy ((4/3) V), a quad on the body nothing. Slip
// nodes then slide along u = 0 only as far as the wall keeps following the body (without it, a
// limb's tip or a fin's edge is given up for better cells: the wall's quads bridge it).
// 0 adds nothing. `body` must outlive g.
void hold_wall_quads(const BlockGrid& grid, const std::vector<Vec3>& target_points,
                     const ImplicitFunction& body, double fidelity, GridProblem& g);

// Gives `p` the geometry of `body` for its constrained vertices: slip on u = 0 (grad u, the
// projection V), feature edges along the body's creases (surface/implicit_features.h);
// tolerances relative to p.length_scale, which must be set. `body` must outlive `p`.
void slide_on(const ImplicitFunction& body, untangle::Problem& p);

// Nodes 0 .. last of the wall-normal lines that start on a crease or corner of the body (two
// or more distinct faces active at the wall node, within 1e-6 of the wall spacing there).
std::vector<bool> crease_line_nodes(const BlockGrid& grid, const ImplicitFunction& body, int last);

// The nodes 0 .. layers of every wall line: the wall and its boundary layer.
std::vector<bool> wall_layer_nodes(const BlockGrid& grid, int layers);

// `marked` grown by `rings` rings of cells: every node of a cell with a marked node is marked,
// `rings` times over.
std::vector<bool> grow_by_cells(const BlockGrid& grid, std::vector<bool> marked, int rings);

// Marks every node of the cells whose scaled Jacobian (`sj`, in for_each_cell order over the
// blocks) is not at least `threshold`.
void mark_cells_below(const BlockGrid& grid, const std::vector<double>& sj, double threshold,
                      std::vector<bool>& marked);

}  // namespace hexmesh

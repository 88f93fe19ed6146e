// Uniform nested refinement of a block grid: every hex split into 8, interfaces kept conforming,
// whole or one block at a time.
#pragma once

#include <functional>
#include <unordered_map>
#include <vector>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/core/block_grid.h"
#include "volume/refined_block.h"

namespace hexmesh {

// The grid with every cell split into 8: a block of (ni, nj, nk) nodes becomes
// (2 ni - 1, 2 nj - 1, 2 nk - 1). Nesting: node v < coarse.points.size() of the result is
// coarse node v, at exactly the same position, and sits at the even fine indices (2i, 2j, 2k)
// of every block; so level L is exactly every other node of level L + 1. New nodes are created
// once per coarse entity (edge midpoints keyed by their 2 coarse node ids, face centres by
// their 4, cell centres per cell) and numbered after the coarse nodes, block by block, so
// blocks still share their interface nodes.
//
// Positions: the same smooth map x(xi) sampled at the half-integer indices, by tensor-product
// interpolation along the block's grid lines in index space, one direction after the other
// (i, then j, then k): cubic Lagrange (-1, 9, 9, -1)/16 where a line has two coarse nodes on
// each side, quadratic (3, 6, -1)/8 at line ends, linear on 2-node lines; a coarse node where
// the line turns by more than 45 degrees (a crease of the wall it follows) counts as a line
// end for the stencils on either side. This keeps curved walls curved and a geometric
// stretching nearly geometric (ratio r becomes ~sqrt(r)), and keeps the lines next to a crease
// on their side of it. Along an index direction with a "wall" face at an end (the
// wall-normal lines) each new node then slides along the chord of its coarse cell (keeping
// its offset across it, the line's curvature) to where the refined stretching law splits
// the cell: into two cells of ratio sqrt(L / L_w), L the cell's length and L_w that of the
// cell next to it on the wall side (for the wall cell: sqrt(L_o / L), L_o the cell beyond).
// So a boundary layer of ratio r becomes one of ratio sqrt(r), exactly, its first cell
// h / (1 + sqrt(r)) (refined_wall_layers), up to its last layer, next to which the ratio
// changes: there the stencils in the index overshoot, which made the fine spacing shrink
// outwards (ratios down to 0.99 on a sphere, 0.2 on a box with a cylinder, whose lines
// change ratio more sharply). A node shared
// by blocks takes the value of the first block that reaches it (the blocks agree up to
// round-off where their lines coincide, except next to a crease, where the order of the
// index directions can change which stencils stop).
//
// Kinds: coarse nodes keep theirs. A new node on a block face with patch "wall" is slip
// (feature_edge when it is the midpoint of a wall edge whose two ends are feature_edge or
// corner nodes: the crease runs along that edge), on any other patch ("farfield", ...)
// fixed, else interior; a node on several faces takes the most constrained kind. Blocks keep
// their names and patches. Parallel (TBB) over grid lines and cells.
BlockGrid refine_grid(const BlockGrid& coarse);

// refine_grid one block at a time, in block order. Memory: the coarse grid (by reference),
// one fine block, and the new nodes on block faces: the constructor walks every block face
// once to count each such node's blocks and give it its kind (the most constrained of its
// blocks'); a node is dropped once its last block has taken it. Throws
// std::invalid_argument when the grid's kinds are not sized like its points.
class BlockRefiner {
  public:
    // place(x, kind): where a new node on a block face goes (e.g. a wall node projected onto
    // the body); called once per such node, in parallel, before any block receives it, so a
    // node shared by blocks gets one position. Where it moves a wall node by d, the new
    // interior nodes of the node's wall-normal line in the block (not yet placed by another
    // block) move by d (1 - s / S), s their length along the line from the wall, S the line's:
    // its cells all stretch alike, so the first layer keeps its thickness and the line its
    // growth ratios. Nodes inside a block stay where interpolated otherwise.
    using Place = std::function<Vec3(const Vec3& x, VertexKind kind)>;

    explicit BlockRefiner(const BlockGrid& coarse);

    // Fine block b (blocks are taken in order 0, 1, ..., each once).
    RefinedBlock refine(size_t b, const Place& place = nullptr);

    // Takes block b's turn without making it: only the nodes on its faces are interpolated
    // and placed, those it reaches first, exactly as refine(b) would (a node on a block face
    // depends on that face alone), and the ids it would use are counted. So the blocks after
    // it get the same nodes and ids as after refine(b): a process that makes some blocks of
    // a grid and skips the others makes them as the whole refinement does, bit for bit.
    // Costs the block's faces, not its cells.
    void skip(size_t b, const Place& place = nullptr);

    // Points of the whole fine grid (refine_grid(coarse).points.size()), and its cells.
    Id num_points() const { return num_points_; }
    Id num_cells() const { return 8 * coarse_.num_cells(); }

  private:
    // The new node of a coarse edge or face (its 2 or 4 coarse ids, sorted, padded).
    struct FaceNode {
        Id id = -1;  // assigned by the first block that reaches it
        Vec3 x = Vec3::Zero();
        VertexKind kind = VertexKind::interior;
        int remaining = 0;  // occurrences (block, fine node) not yet taken
    };
    using Key = std::array<Id, 4>;
    using FaceNodes = std::unordered_map<Key, FaceNode, ArrayHash<Id, 4>>;
    // A block-face node of the block being taken (its fine index m) and its entry.
    struct Reached {
        Id m;
        FaceNodes::iterator e;
    };

    const Block& next(size_t b);  // block b, checking the order
    // Visits the fine nodes of `block` (fine dims f) in refine_grid's order, giving new nodes
    // their ids: visit.coarse(m, id), visit.inner(m, id) (only counted, unless
    // Visit::each_inner_node), visit.face(m, reached, first).
    template <class Visit>
    void number(const Block& block, const Dims& f, Visit&& visit);
    // Places the block-face nodes reached first (place, then carry_wall_moves), gives those
    // reached again their first position, and drops the nodes no block will reach again.
    template <class At, class Movable>
    void settle(const Block& fine, const std::vector<Reached>& first,
                const std::vector<Reached>& again, const Place& place, bool faces_only, At&& at,
                Movable&& movable);

    const BlockGrid& coarse_;
    FaceNodes face_nodes_;
    Id num_points_ = 0, next_id_ = 0;
    size_t next_block_ = 0;
};

}  // namespace hexmesh

// The QualityReport of a block grid read from its blocks, whole or block by block as the
// grid is made.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/quality/mesh_quality.h"

namespace hexmesh {

// The same numbers as measure_quality(to_hex_mesh(grid)) to rounding (a cell on a block
// boundary computes its boundary faces from its own point order, and the mean's sum runs in
// another order), read from the blocks in one pass: faces inside a block meet the structured
// neighbour and are computed once, only faces on block boundaries are matched by node ids,
// and neither an unstructured copy nor per-cell arrays are made. A BlockQuality over the
// blocks in order.
QualityReport measure_quality(const BlockGrid& grid);

// Where the cells of a block added sit in the whole grid's numbering (to_hex_mesh order), for
// blocks measured apart: the block added is the part at `offset` (in cells) of a block of
// `whole` cells whose first cell is `first`, so its cell (i, j, k) is cell first + (i +
// offset[0]) + whole.ni (j + offset[1]) + whole.ni whole.nj (k + offset[2]). whole empty:
// the block added is whole. first < 0: numbered after the cells added before (one process
// adding every block in order).
struct CellNumbering {
    Id first = -1;
    std::array<int, 3> offset = {0, 0, 0};
    Dims whole;
};

// measure_quality of a block grid taken block by block, so that a grid too large to hold can
// be measured as its blocks are made: add() each block in order, then report(). Cells are
// numbered in to_hex_mesh order (the lower cell owns a face). The faces on a block's boundary
// wait, by their node ids, for the cell across; those never paired are boundary faces. Holds
// the open faces (their points, and the centre and volume of their cell) and the node ids of
// the paired ones: memory of the order of the block faces, not of the cells.
class BlockQuality {
  public:
    BlockQuality();
    ~BlockQuality();
    BlockQuality(const BlockQuality&) = delete;
    BlockQuality& operator=(const BlockQuality&) = delete;

    // Adds `block`, whose node ids index grid.points. When the block's grid numbers its
    // points on its own (one block made at a time), ids[v] is point v's id in the whole grid,
    // which is what pairs faces across blocks. Throws std::invalid_argument, naming the
    // cells, when a face is shared by more than two cells.
    // `numbering`: where the block's cells sit in the whole grid (the blocks of one grid, or
    // parts of them, measured by several processes, each adding its own).
    void add(const BlockGrid& grid, const Block& block, const std::vector<Id>* ids = nullptr,
             const CellNumbering& numbering = {});

    QualityReport report() const;

    // What has been added, as bytes for another process; merge() adds another BlockQuality's
    // pack() to this one (its cells, and its open faces paired with these): the blocks of one
    // grid measured apart, then put together.
    std::string pack() const;
    void merge(const std::string& packed);

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace hexmesh

// The quality report of a block grid against its body: cell and face quality, wall layers,
// surface fidelity; whole, or block by block as a grid too large to hold is made.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/wall_metrics.h"
#include "volume/stretching.h"

namespace hexmesh {

// measure_grid block by block: add() each block of the grid in order, then report(). The
// grid passed with a block holds its points: the whole grid, or a grid of that block alone
// numbered on its own, with `ids` its points' ids in the whole grid (BlockQuality pairs the
// faces across blocks by them). Holds the open block faces and the wall as triangles (for
// the Hausdorff distance), never the cells.
class GridMeter {
  public:
    GridMeter(const ImplicitFunction& body, const WallLayers& law = {},
              const TriangleSurface* surface = nullptr);

    // `numbering`: where the block's cells sit in the whole grid, for the blocks of one grid
    // (or parts of blocks) measured by several processes, each adding its own (in order),
    // then merged. A worst cell is placed in its whole block (its name, its indices there).
    void add(const BlockGrid& grid, const Block& block, const std::vector<Id>* ids = nullptr,
             const CellNumbering& numbering = {});
    GridReport report() const;

    // What has been added, as bytes for another process; merge() adds another GridMeter's
    // pack() (the same body, law and surface; other blocks of the same grid) to this one.
    // The report of meters merged is the report of one meter given all their blocks, but for
    // the rounding of sums (means).
    std::string pack() const;
    void merge(const std::string& packed);

  private:
    std::optional<CellPlace> place(Id cell) const;  // of a cell added, by its id

    const ImplicitFunction& body_;
    const TriangleSurface* surface_;
    BlockQuality quality_;
    WallMeter wall_;
    bool has_wall_ = false;
    TriangleSurface wall_triangles_;  // gathered only with a surface
    double wall_edge_length_ = 0;     // over the cell edges with two slip ends
    Id wall_edges_ = 0;
    double max_slip_value_ = 0;  // max |u| over slip nodes
    // The blocks added, in order: to place the worst cell.
    struct Added {
        std::string name;
        Dims cells;
        std::array<bool, 6> wall;  // BlockFace order
        Id first_cell = 0;         // of the whole block it is part of (CellNumbering)
        std::array<int, 3> offset = {0, 0, 0};
        Dims whole;
    };
    Id cells_ = 0;  // cells added
    std::vector<Added> added_;
};

// Quality metrics of `grid`, surface fidelity against `body` over its slip nodes, the
// wall-layer metrics against `law` and, when `surface` is given, the Hausdorff distance
// between the grid's wall and it. A GridMeter over the blocks in order.
GridReport measure_grid(const BlockGrid& grid, const ImplicitFunction& body,
                        const WallLayers& law = {}, const TriangleSurface* surface = nullptr);

}  // namespace hexmesh

// The `run` stage refine: nested refinement on the body — blocks split (BlockRefiner), new wall
// nodes onto u = 0, a local polish; whole, or block by block — and the grid-convergence family.
#pragma once

#include <functional>
#include <ostream>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/pipeline/job.h"
#include "hexmesh/quality/grid_report.h"
#include "untangle/tet_energy.h"
#include "volume/refine.h"
#include "volume/stretching.h"

namespace hexmesh {

struct RefinementOptions {
    int sweeps = 4;  // descent steps of the block-diagonal solver on the new nodes
    double theta = untangle::default_theta;  // volume weight: the untangler's default
    std::ostream* log = nullptr;             // the solver's progress lines
};

struct RefinementResult {
    BlockGrid grid;
    Id projected = 0;           // new wall nodes moved onto u = 0 (or onto a crease)
    double max_projection = 0;  // the longest such move, in geometry units
};

// One level finer than `coarse` (a grid on `body`, e.g. from `run` or a previous level), made
// block by block (refine_blocks) and assembled: node v < coarse.points.size() of the result
// is coarse node v, at its exact position, so the levels are nested.
RefinementResult refine_on_body(const BlockGrid& coarse, const ImplicitFunction& body,
                                const RefinementOptions& options = {});

struct RefinementStats {
    Id points = 0;              // nodes of the fine grid
    Id projected = 0;           // new wall nodes moved onto u = 0 (or onto a crease)
    double max_projection = 0;  // the longest such move, in geometry units
    Id polished = 0;            // new nodes given to the local solver (free in the polish)
};

// Receives each finished fine block (see BlockRefiner: its points numbered on their own,
// `ids` their ids in the whole fine grid); it may keep, measure or write it, then drop it.
using BlockSink = std::function<void(RefinedBlock& block)>;

// One level finer than `coarse`, one block at a time, so that memory holds the coarse grid,
// one fine block and the new nodes on block faces (see BlockRefiner), not the fine grid. Each
// block: BlockRefiner splits it, its new slip nodes go onto u = 0 of `body` (project_to_surface)
// and its new feature_edge nodes onto their crease, as they are first reached (a node shared by
// blocks is placed once), and the new nodes of their wall-normal lines follow them (see
// BlockRefiner::Place); then `sweeps` steps of the block-diagonal solver (slip on u = 0) over the
// new nodes of the cells that touch a new wall node, each cell's target the box of its own edge
// lengths after interpolation (as in optimize_grid). The interpolated interior needs no polish and
// is left as it is; so are the new nodes on block interfaces, which every block holding
// them takes as the first one placed them (the blocks stay conforming, and each is
// finished alone). Where the polish leaves a cell below the worst scaled Jacobian of the
// block's interpolated cells, that cell's new nodes return to their interpolated
// positions, so refinement never lowers the interpolation's min scaled Jacobian. Coarse
// nodes keep their exact positions. Inverted cells (there should be none) are untangled
// by the same local solver. Then `sink` gets the block. Blocks run in order, each one
// multi-threaded (TBB). With `made`, only the blocks b with (*made)[b] are made and given to
// `sink`; the others are skipped (BlockRefiner::skip: their faces only), and the blocks
// made are the same, bit for bit, as when every block is (one process of several, each
// making its share of the grid). `polished` then counts the blocks made.
RefinementStats refine_blocks(const BlockGrid& coarse, const ImplicitFunction& body,
                              const RefinementOptions& options, const BlockSink& sink,
                              const std::vector<bool>* made = nullptr);

// A part of a block of the level finer than a grid, made by one process: the fine cells
// [lo, hi) along index direction `axis` and all of them along the other two (the whole block
// when lo = 0 and hi is its fine cell count along `axis`).
struct BlockPiece {
    size_t block = 0;
    int axis = 0, lo = 0, hi = 0;
    int process = 0;
    Id cells = 0;  // fine cells
};

// The pieces of the level finer than `grid` that `processes` processes make, in block order,
// then along their axis. With no more processes than blocks, the blocks whole, by decreasing
// cell count each to the process with the fewest cells so far (the lowest rank among equals),
// so the shares differ by at most the largest block. With more, the largest piece is halved
// (between two coarse cells: each coarse cell's fine cells stay in one piece) until there is
// one per process or no piece has two coarse cells left, along its block's longest index
// direction among those
// without a "wall" face at either end (so every wall-normal line stays in one piece, and is
// measured whole), the longest of all when each has one.
std::vector<BlockPiece> share_blocks(const BlockGrid& grid, int processes);

// The nested family level_1 = `coarse`, level_2, ..., level_`levels` (levels >= 1), each
// level refine_on_body of the one before.
std::vector<BlockGrid> refine_family(const BlockGrid& coarse, const ImplicitFunction& body,
                                     int levels, const RefinementOptions& options = {});

// The boundary-layer law level `level` (1 = the coarse grid) of a family follows when level 1
// follows `law`: each cell is split in two along the wall normal, so per level the growth
// ratio r becomes sqrt(r), the first height h becomes h / (1 + sqrt(r)) (about h / 2: the
// first coarse cell holds two fine cells of ratio sqrt(r)) and the layers double.
WallLayers refined_wall_layers(const WallLayers& law, int level);

// The stage: with c.refinement.levels = N > 1, job.grid() is level 1 of a nested family (refused
// first if a solver cannot take it, see refuse_invalid), and levels 2 .. N are appended to
// job.levels, each refine_on_body of the one before (the polish of refined levels keeps its
// own theta, RefinementOptions: volume-weighted, it holds the interpolated wall spacing), with
// their reports (measure_level) appended to job.reports.
void refine_levels(Job& job);

// One row of a grid-convergence study table.
struct FamilyLevel {
    int level = 1;
    Id cells = 0;
    double min_scaled_jacobian = 0, mean_scaled_jacobian = 0;
    double first_layer = 0;            // mean first-layer height at the wall (0: no wall)
    double growth_ratio = 0;           // mean growth ratio along the wall-normal lines
    double max_non_orthogonality = 0;  // degrees
};

FamilyLevel family_level(int level, const GridReport& report);

// The study table printed by `run` (a header line, one line per level).
std::string format_family_table(const std::vector<FamilyLevel>& levels);

// family.json: {"refinement_ratio": 2, "levels": [{"level", "directory", "cells", ...}]}.
std::string family_json(const std::vector<FamilyLevel>& levels);

}  // namespace hexmesh

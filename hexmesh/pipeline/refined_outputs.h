// The formats of a refined level beyond its VTK files: an OpenFOAM case decomposed as the
// processes made the level, or any export format of the level gathered at rank 0.
#pragma once

#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/pipeline/refine.h"
#include "io/flow_spec.h"
#include "volume/refine.h"

namespace hexmesh {

// The pieces of the fine level this process made (their index in share_blocks' list, and
// the piece), kept to be written.
struct MadeBlocks {
    std::vector<size_t> index;
    std::vector<RefinedBlock> blocks;
};

// Writes the level finer than `coarse` (its pieces made by the processes as `pieces` says,
// this process's in `made`) in each of `formats` (export format names) into `folder` (the
// output's staging folder, shared by the processes), named as export_file_name names them
// ("grid"): with several processes, "openfoam" as a decomposed case (every process writes
// its processor folder, see write_openfoam_processor; each piece a whole block) and the other
// formats from the level gathered whole at rank 0 (split blocks joined again); with one,
// every format from the level held whole. Collective (every step in ranks::together, so an
// error on one process stops every one). Returns the names written in `folder` (at rank 0).
std::vector<std::string> write_refined_formats(const BlockGrid& coarse,
                                               const std::vector<BlockPiece>& pieces,
                                               MadeBlocks& made,
                                               const std::vector<std::string>& formats,
                                               const std::string& folder, const FlowSpec& flow);

}  // namespace hexmesh

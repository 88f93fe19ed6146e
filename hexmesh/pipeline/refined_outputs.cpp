#include "hexmesh/pipeline/refined_outputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <unordered_map>

#include "hexmesh/core/bytes.h"
#include "hexmesh/pipeline/ranks.h"
#include "io/export_grid.h"
#include "io/grid_faces.h"
#include "io/openfoam_mesh.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

// This process's blocks as one grid numbered on its own (a node shared by its blocks is one
// point), with each point's id in the whole level.
BlockGrid share_of(const MadeBlocks& made, std::vector<Id>& global_ids) {
    BlockGrid share;
    std::unordered_map<Id, Id> local;  // of the nodes that blocks may share
    for (const RefinedBlock& piece : made.blocks) {
        Block block = piece.grid.blocks[0];
        for (size_t m = 0; m < piece.ids.size(); ++m) {
            const Id id = piece.ids[m];
            Id& at = block.node_ids[m];
            if (piece.shared[m] || piece.coarse[m]) {
                const auto [it, inserted] = local.try_emplace(id, Id(share.points.size()));
                at = it->second;
                if (!inserted) continue;
            } else {
                at = Id(share.points.size());
            }
            share.points.push_back(piece.grid.points[m]);
            share.kinds.push_back(piece.grid.kinds[m]);
            global_ids.push_back(id);
        }
        share.blocks.push_back(std::move(block));
    }
    return share;
}

// Writes this process's processor folder of the decomposed case `case_dir`.
void write_processor(const BlockGrid& coarse, const std::vector<int>& owner, const MadeBlocks& made,
                     const std::string& case_dir, const FlowSpec& flow) {
    const GridFaces coarse_faces = make_grid_faces(coarse);
    ProcessorShare p;
    p.process = ranks::rank();
    p.processes = ranks::size();
    p.patches = coarse_faces.patch_names;
    p.wall_extent = wall_extent(coarse);
    // A fine cell (i, j, k) lies in coarse cell (i / 2, j / 2, k / 2) of its block: the cell
    // across a fine face on a block face is in the coarse cell across it.
    p.process_across = [&](int b, int face, int i, int j, int k) {
        const size_t block = made.index[size_t(b)];
        const Dims cells = coarse.blocks[block].cells();
        const Id across =
            coarse_faces.across[block][size_t(face)]
                               [size_t(face_cell_index(cells, face, i / 2, j / 2, k / 2))];
        if (across < 0) return -1;
        const auto& first = coarse_faces.first_cell;
        const size_t other =
            size_t(std::upper_bound(first.begin(), first.end(), across) - first.begin()) - 1;
        return owner[other];
    };
    BlockGrid share = share_of(made, p.global_ids);
    // The block interfaces that other processes' blocks meet take the patch shared_faces.
    for (size_t b = 0; b < share.blocks.size(); ++b) {
        const size_t block = made.index[b];
        for (int face = 0; face < 6; ++face) {
            std::string& patch = share.blocks[b].face_patch[size_t(face)];
            if (!patch.empty()) continue;
            int others = 0, own = 0;
            for (const Id across : coarse_faces.across[block][size_t(face)]) {
                const auto& first = coarse_faces.first_cell;
                const size_t other =
                    size_t(std::upper_bound(first.begin(), first.end(), across) - first.begin()) -
                    1;
                (across >= 0 && owner[other] != p.process ? others : own) += 1;
            }
            if (others > 0 && own > 0)
                throw std::runtime_error(fmt::format(
                    "block {}: a face met by blocks of this process and of others; the "
                    "decomposed OpenFOAM case needs each block face on one process's side",
                    coarse.blocks[block].name));
            if (others > 0) patch = ProcessorShare::shared_faces;
        }
    }
    write_openfoam_processor(share, p, case_dir, flow);
}

// The whole level at rank 0, from every process's blocks (collective; elsewhere empty).
BlockGrid gather_level(const BlockGrid& coarse, const MadeBlocks& made) {
    ByteWriter out;
    out.put(made.blocks.size());
    for (size_t n = 0; n < made.blocks.size(); ++n) {
        const RefinedBlock& piece = made.blocks[n];
        const Block& block = piece.grid.blocks[0];
        out.put(made.index[n]), out.put(block.name), out.put(block.nodes);
        for (const std::string& patch : block.face_patch) out.put(patch);
        out.put(piece.ids), out.put(piece.grid.points), out.put(piece.grid.kinds);
        out.put(piece.fine_points);
    }
    const std::vector<std::string> all = ranks::gather(out.bytes());
    BlockGrid level;
    if (all.empty()) return level;
    std::vector<RefinedBlock> pieces(coarse.blocks.size());
    for (const std::string& bytes : all) {
        ByteReader in(bytes);
        for (size_t n = in.next<size_t>(); n > 0; --n) {
            RefinedBlock& piece = pieces.at(in.next<size_t>());
            Block& block = piece.grid.blocks.emplace_back();
            in.get(block.name), in.get(block.nodes);
            for (std::string& patch : block.face_patch) in.get(patch);
            in.get(piece.ids), in.get(piece.grid.points), in.get(piece.grid.kinds);
            in.get(piece.fine_points);
        }
    }
    level.points = coarse.points;
    level.kinds = coarse.kinds;
    for (RefinedBlock& piece : pieces) add_refined_block(level, std::move(piece));
    return level;
}

}  // namespace

std::vector<std::string> write_refined_formats(const BlockGrid& coarse,
                                               const std::vector<int>& owner, MadeBlocks& made,
                                               const std::vector<std::string>& formats,
                                               const std::string& folder, const FlowSpec& flow) {
    std::vector<std::string> names, gathered;
    for (const std::string& format : formats) {
        if (format == "openfoam" && ranks::size() > 1) {
            const std::string name = export_file_name(format, "grid", coarse);
            write_processor(coarse, owner, made, (fs::path(folder) / name).string(), flow);
            names.push_back(name);
        } else {
            gathered.push_back(format);
        }
    }
    if (gathered.empty()) return names;
    const BlockGrid level = gather_level(coarse, made);
    made = {};  // held whole now, at rank 0
    if (ranks::rank() != 0) return names;
    for (const std::string& format : gathered) {
        const std::string name = export_file_name(format, "grid", level);
        write_grid_format(level, format, (fs::path(folder) / name).string(), flow);
        names.push_back(name);
    }
    return names;
}

}  // namespace hexmesh

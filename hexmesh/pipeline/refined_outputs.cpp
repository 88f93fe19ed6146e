#include "hexmesh/pipeline/refined_outputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <iterator>
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

// The process making fine cell `at` (fine indices) of block b (a coarse cell's fine cells
// are in one piece, see share_blocks).
int process_of(const std::vector<BlockPiece>& pieces, size_t b, const std::array<int, 3>& at) {
    for (const BlockPiece& p : pieces)
        if (p.block == b && at[size_t(p.axis)] >= p.lo && at[size_t(p.axis)] < p.hi)
            return p.process;
    return -1;
}

// The bounding box of the "wall" faces of this process's pieces (empty: lo above hi).
Box3 wall_box_of(const MadeBlocks& made) {
    Box3 box{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
    for (const RefinedBlock& piece : made.blocks) {
        const Block& block = piece.grid.blocks[0];
        const Dims d = block.nodes;
        for (int face = 0; face < 6; ++face) {
            if (block.face_patch[size_t(face)] != "wall") continue;
            const int axis = face / 2;
            int lo[3] = {0, 0, 0}, hi[3] = {d.ni, d.nj, d.nk};
            lo[axis] = face % 2 ? d[axis] - 1 : 0;
            hi[axis] = lo[axis] + 1;
            for (int k = lo[2]; k < hi[2]; ++k)
                for (int j = lo[1]; j < hi[1]; ++j)
                    for (int i = lo[0]; i < hi[0]; ++i) {
                        const Vec3& x = piece.grid.points[size_t(block.node(i, j, k))];
                        box.lo = box.lo.cwiseMin(x), box.hi = box.hi.cwiseMax(x);
                    }
        }
    }
    return box;
}

// The largest extent of the whole level's wall, from every process's pieces (collective),
// as write_openfoam_mesh measures it on the level held whole.
double wall_extent_of_level(const MadeBlocks& made) {
    Box3 box;
    ranks::together([&] { box = wall_box_of(made); });
    const std::vector<double> far =
        ranks::max({-box.lo.x(), -box.lo.y(), -box.lo.z(), box.hi.x(), box.hi.y(), box.hi.z()});
    const Vec3 size(far[3] + far[0], far[4] + far[1], far[5] + far[2]);
    return size.x() >= 0 ? size.maxCoeff() : 0;
}

// Writes this process's processor folder of the decomposed case `case_dir`; `extent`: the
// whole level's wall extent.
void write_processor(const BlockGrid& coarse, const std::vector<BlockPiece>& pieces,
                     const MadeBlocks& made, double extent, const std::string& case_dir,
                     const FlowSpec& flow) {
    const GridFaces coarse_faces = make_grid_faces(coarse);
    ProcessorShare p;
    p.process = ranks::rank();
    p.processes = ranks::size();
    p.patches = coarse_faces.patch_names;
    p.wall_extent = extent;
    // Fine cell (i, j, k) of a piece is fine cell (i, j, k) + its offset along the axis of
    // its block, in coarse cell (i / 2, j / 2, k / 2): across a cut, the cell is the next
    // piece's; across a block face, in the coarse cell across, in whichever piece holds it.
    p.process_across = [&](int b, int face, int i, int j, int k) {
        const BlockPiece& piece = pieces[made.index[size_t(b)]];
        std::array<int, 3> at = {i, j, k};
        at[size_t(piece.axis)] += piece.lo;
        const int axis = face / 2;
        if (axis == piece.axis) {
            std::array<int, 3> next = at;
            next[size_t(axis)] += face % 2 ? 1 : -1;
            const int fine = 2 * coarse.blocks[piece.block].cells()[axis];
            if (next[size_t(axis)] >= 0 && next[size_t(axis)] < fine)
                return process_of(pieces, piece.block, next);
        }
        const Dims cells = coarse.blocks[piece.block].cells();
        const Id across = coarse_faces.across[piece.block][size_t(face)][size_t(
            face_cell_index(cells, face, at[0] / 2, at[1] / 2, at[2] / 2))];
        if (across < 0) return -1;
        const auto& first = coarse_faces.first_cell;
        const size_t other =
            size_t(std::upper_bound(first.begin(), first.end(), across) - first.begin()) - 1;
        const Dims c = coarse.blocks[other].cells();
        const Id in = across - first[other];
        const std::array<int, 3> fine = {int(2 * (in % c.ni)), int(2 * (in / c.ni % c.nj)),
                                         int(2 * (in / (Id(c.ni) * c.nj)))};
        return process_of(pieces, other, fine);
    };
    BlockGrid share = share_of(made, p.global_ids);
    // The interfaces (and cuts) that other processes' cells meet take the patch shared_faces.
    for (size_t b = 0; b < share.blocks.size(); ++b) {
        const Dims d = share.blocks[b].cells();
        for (int face = 0; face < 6; ++face) {
            std::string& patch = share.blocks[b].face_patch[size_t(face)];
            if (!patch.empty()) continue;
            int others = 0, own = 0;
            const int axis = face / 2, u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
            std::array<int, 3> at;
            at[size_t(axis)] = face % 2 ? d[axis] - 1 : 0;
            for (at[size_t(v)] = 0; at[size_t(v)] < d[v]; ++at[size_t(v)])
                for (at[size_t(u)] = 0; at[size_t(u)] < d[u]; ++at[size_t(u)]) {
                    const int across = p.process_across(int(b), face, at[0], at[1], at[2]);
                    (across >= 0 && across != p.process ? others : own) += 1;
                }
            if (others > 0 && own > 0)
                throw std::runtime_error(fmt::format(
                    "block {}: a face met by cells of this process and of others; the "
                    "decomposed OpenFOAM case needs each block face on one process's side",
                    share.blocks[b].name));
            if (others > 0) patch = ProcessorShare::shared_faces;
        }
    }
    write_openfoam_processor(share, p, case_dir, flow);
}

// This process's pieces as bytes, for join_level at rank 0.
std::string pack_pieces(const MadeBlocks& made) {
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
    return out.bytes();
}

// The whole level from every process's pack_pieces (`all`), split blocks joined again.
BlockGrid join_level(const BlockGrid& coarse, const std::vector<BlockPiece>& pieces,
                     const std::vector<std::string>& all) {
    BlockGrid level;
    if (all.empty()) return level;
    std::vector<RefinedBlock> parts(pieces.size());
    for (const std::string& bytes : all) {
        ByteReader in(bytes);
        for (size_t n = in.next<size_t>(); n > 0; --n) {
            RefinedBlock& piece = parts.at(in.next<size_t>());
            Block& block = piece.grid.blocks.emplace_back();
            in.get(block.name), in.get(block.nodes);
            for (std::string& patch : block.face_patch) in.get(patch);
            in.get(piece.ids), in.get(piece.grid.points), in.get(piece.grid.kinds);
            in.get(piece.fine_points);
            piece.shared.assign(piece.ids.size(), false);  // not needed to write it
            piece.coarse.assign(piece.ids.size(), false);
        }
    }
    level.points = coarse.points;
    level.kinds = coarse.kinds;
    // Pieces come in block order, then along their axis: a block split is joined again.
    for (size_t p = 0; p < pieces.size();) {
        size_t end = p + 1;
        while (end < pieces.size() && pieces[end].block == pieces[p].block) ++end;
        if (end == p + 1) {
            add_refined_block(level, std::move(parts[p]));
        } else {
            const std::vector<RefinedBlock> split(std::make_move_iterator(parts.begin() + p),
                                                  std::make_move_iterator(parts.begin() + end));
            add_refined_block(level, join_parts(split, pieces[p].axis));
        }
        p = end;
    }
    return level;
}

}  // namespace

std::vector<std::string> write_refined_formats(const BlockGrid& coarse,
                                               const std::vector<BlockPiece>& pieces,
                                               MadeBlocks& made,
                                               const std::vector<std::string>& formats,
                                               const std::string& folder, const FlowSpec& flow) {
    std::vector<std::string> names, gathered;
    for (const std::string& format : formats) {
        if (format == "openfoam" && ranks::size() > 1) {
            const std::string name = export_file_name(format, "grid", coarse);
            const double extent = wall_extent_of_level(made);
            ranks::together([&] {
                write_processor(coarse, pieces, made, extent, (fs::path(folder) / name).string(),
                                flow);
            });
            names.push_back(name);
        } else {
            gathered.push_back(format);
        }
    }
    if (gathered.empty()) return names;
    // The level gathered whole at rank 0.
    std::string mine;
    ranks::together([&] {
        mine = pack_pieces(made);
        made = {};
    });
    const std::vector<std::string> all = ranks::gather(mine);
    mine.clear();
    ranks::together([&] {
        if (ranks::rank() != 0) return;
        const BlockGrid level = join_level(coarse, pieces, all);
        for (const std::string& format : gathered) {
            const std::string name = export_file_name(format, "grid", level);
            write_grid_format(level, format, (fs::path(folder) / name).string(), flow);
            names.push_back(name);
        }
    });
    return names;
}

}  // namespace hexmesh

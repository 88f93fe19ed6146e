#include "io/grid_faces.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"

namespace hexmesh {
namespace {

using FaceKey = std::array<Id, 4>;

FaceKey sorted_key(std::array<Id, 4> nodes) {
    std::sort(nodes.begin(), nodes.end());
    return nodes;
}

// Where one cell face on a block boundary lives: block, block face, index on that face.
struct FaceSlot {
    int block = -1, face = -1;
    Id index = -1, cell = -1;
};

}  // namespace

GridFaces make_grid_faces(const BlockGrid& grid) {
    GridFaces out;
    const int nblocks = int(grid.blocks.size());
    out.first_cell.resize(nblocks);
    out.across.resize(nblocks);
    out.face_patch_index.assign(nblocks, {-1, -1, -1, -1, -1, -1});
    Id next = 0;
    for (int b = 0; b < nblocks; ++b) {
        out.first_cell[b] = next;
        const Dims c = grid.blocks[b].cells();
        next += c.count();
        // Faces inside the block: (ni-1) nj nk + ni (nj-1) nk + ni nj (nk-1) for cell dims.
        out.internal_faces += Id(c.ni - 1) * c.nj * c.nk + Id(c.ni) * (c.nj - 1) * c.nk +
                              Id(c.ni) * c.nj * (c.nk - 1);
    }

    // Interface faces (block faces without a patch name) meet by their sorted node ids.
    std::unordered_map<FaceKey, FaceSlot, ArrayHash<Id, 4>> open;
    for (int b = 0; b < nblocks; ++b) {
        const Block& block = grid.blocks[b];
        const Dims c = block.cells();
        for (int face = 0; face < 6; ++face) {
            const int axis = face / 2;
            const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
            out.across[b][face].assign(Id(c[u]) * c[v], -1);
            if (!block.face_patch[face].empty()) continue;
            int ijk[3];
            ijk[axis] = face % 2 ? c[axis] - 1 : 0;
            for (ijk[v] = 0; ijk[v] < c[v]; ++ijk[v])
                for (ijk[u] = 0; ijk[u] < c[u]; ++ijk[u]) {
                    const FaceSlot slot{b, face, face_cell_index(c, face, ijk[0], ijk[1], ijk[2]),
                                        out.first_cell[b] + c.flat(ijk[0], ijk[1], ijk[2])};
                    const FaceKey key =
                        sorted_key(cell_face_nodes(block, ijk[0], ijk[1], ijk[2], face));
                    auto [it, inserted] = open.emplace(key, slot);
                    if (inserted) continue;
                    FaceSlot& other = it->second;
                    if (other.cell < 0 || other.cell == slot.cell) {
                        throw std::invalid_argument(fmt::format(
                            "block grid: a face of cell {} (block '{}') is shared by more than "
                            "two cells",
                            slot.cell, block.name));
                    }
                    out.across[b][face][slot.index] = other.cell;
                    out.across[other.block][other.face][other.index] = slot.cell;
                    other.cell = -1;  // matched: a third copy is an error
                    ++out.internal_faces;
                }
        }
    }

    auto patch_index = [&](const std::string& name) {
        for (int p = 0; p < int(out.patch_names.size()); ++p)
            if (out.patch_names[p] == name) return p;
        out.patch_names.push_back(name);
        return int(out.patch_names.size()) - 1;
    };
    for (int b = 0; b < nblocks; ++b)
        for (int face = 0; face < 6; ++face) {
            const std::vector<Id>& across = out.across[b][face];
            const Id open_faces = std::count(across.begin(), across.end(), Id(-1));
            if (open_faces == 0) continue;
            const std::string& name = grid.blocks[b].face_patch[face];
            // A face without a patch is an interface: every cell face on it meets another
            // block's, or the blocks do not conform there.
            if (name.empty())
                throw std::invalid_argument(fmt::format(
                    "block grid: face {} of block '{}' is an interface (no patch), but {} of its "
                    "{} cell "
                    "faces meet no other block's: the blocks do not conform there",
                    block_face_names[face], grid.blocks[b].name, open_faces, across.size()));
            out.face_patch_index[b][face] = patch_index(name);
            out.boundary_faces += open_faces;
        }
    return out;
}

std::vector<Id> patch_face_counts(const BlockGrid& grid, const GridFaces& faces) {
    std::vector<Id> counts(faces.patch_names.size(), 0);
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        const Dims c = grid.blocks[b].cells();
        for (int face = 0; face < 6; ++face)
            if (const int p = faces.face_patch_index[b][face]; p >= 0)
                counts[size_t(p)] += c.count() / c[face / 2];
    }
    return counts;
}

}  // namespace hexmesh

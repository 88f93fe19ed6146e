#include "hexmesh/core/block_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace hexmesh {

Id BlockGrid::num_cells() const {
    Id n = 0;
    for (const Block& b : blocks) n += b.cells().count();
    return n;
}

std::array<Id, 8> cell_nodes(const Block& block, int i, int j, int k) {
    return {block.node(i, j, k),
            block.node(i + 1, j, k),
            block.node(i + 1, j + 1, k),
            block.node(i, j + 1, k),
            block.node(i, j, k + 1),
            block.node(i + 1, j, k + 1),
            block.node(i + 1, j + 1, k + 1),
            block.node(i, j + 1, k + 1)};
}

std::vector<std::array<Id, 8>> cells_not_held(const BlockGrid& grid,
                                              const std::vector<bool>& held) {
    std::vector<std::array<Id, 8>> cells;
    for (const Block& block : grid.blocks) {
        const Dims d = block.cells();
        std::vector<std::vector<std::array<Id, 8>>> slabs(size_t(std::max(d.nk, 0)));
        tbb::parallel_for(0, d.nk, [&](int k) {
            for (int j = 0; j < d.nj; ++j)
                for (int i = 0; i < d.ni; ++i) {
                    const std::array<Id, 8> nodes = cell_nodes(block, i, j, k);
                    if (!std::all_of(nodes.begin(), nodes.end(),
                                     [&](Id v) { return bool(held[v]); }))
                        slabs[k].push_back(nodes);
                }
        });
        for (const auto& slab : slabs) cells.insert(cells.end(), slab.begin(), slab.end());
    }
    return cells;
}

HexMesh to_hex_mesh(const BlockGrid& grid) {
    HexMesh mesh;
    mesh.points = grid.points;
    mesh.hexes.reserve(8 * grid.num_cells());
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& nodes) {
            mesh.hexes.insert(mesh.hexes.end(), nodes.begin(), nodes.end());
        });
    return mesh;
}

}  // namespace hexmesh

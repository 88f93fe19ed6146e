#include "hexmesh/core/block_grid.h"

namespace hexmesh {

Id BlockGrid::num_cells() const {
    Id n = 0;
    for (const Block& b : blocks) n += b.cells().count();
    return n;
}

std::array<Id, 8> cell_nodes(const Block& block, int i, int j, int k) {
    return {block.node(i, j, k),         block.node(i + 1, j, k),
            block.node(i + 1, j + 1, k), block.node(i, j + 1, k),
            block.node(i, j, k + 1),     block.node(i + 1, j, k + 1),
            block.node(i + 1, j + 1, k + 1), block.node(i, j + 1, k + 1)};
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

#include "volume/single_block_grid.h"

#include <tbb/parallel_for.h>

#include <stdexcept>

#include "volume/o_h_grid.h"
#include "volume/surface_placement.h"
#include "volume/tfi.h"

namespace hexmesh {

std::vector<double> two_sided_distances(double length, int cells, const WallLayers& law) {
    const int left = cells / 2, right = cells - left;
    const double split = length * left / cells;
    const std::vector<double> a = wall_distances(split, left, law);
    const std::vector<double> b = wall_distances(length - split, right, law);
    std::vector<double> x(cells + 1);
    for (int m = 0; m <= left; ++m) x[m] = a[m];
    for (int m = 0; m <= right; ++m) x[cells - m] = length - b[m];
    return x;
}

BlockGrid make_single_block_grid(const ImplicitFunction& body, const SingleBlockOptions& options) {
    for (int c : options.cells)
        if (c < 2) throw std::invalid_argument("cells along each axis must be at least 2");
    const Box3 box = body.bounds();
    const Vec3 centre = options.centre.value_or(box.center());
    require_inside(body, centre);
    const int max_cells = std::max({options.cells[0], options.cells[1], options.cells[2]});
    const double h = grid_length_scale(body, max_cells);

    std::array<std::vector<double>, 3> x;
    for (int d = 0; d < 3; ++d)
        x[d] = two_sided_distances(box.size()[d], options.cells[d], options.wall_layers);

    Block block{"body", {options.cells[0] + 1, options.cells[1] + 1, options.cells[2] + 1}, {}, {}};
    block.face_patch.fill("wall");
    const Dims& dims = block.nodes;
    block.node_ids.resize(dims.count());
    BlockGrid grid;
    grid.points.assign(dims.count(), Vec3::Zero());
    grid.kinds.assign(dims.count(), VertexKind::interior);
    for (Id id = 0; id < dims.count(); ++id) block.node_ids[id] = id;

    std::vector<Id> boundary;
    for (int k = 0; k < dims.nk; ++k)
        for (int j = 0; j < dims.nj; ++j)
            for (int i = 0; i < dims.ni; ++i) {
                const Id id = dims.flat(i, j, k);
                grid.points[id] = box.lo + Vec3(x[0][i], x[1][j], x[2][k]);
                if (i == 0 || j == 0 || k == 0 || i == dims.ni - 1 || j == dims.nj - 1 ||
                    k == dims.nk - 1)
                    boundary.push_back(id);
            }
    tbb::parallel_for(size_t(0), boundary.size(), [&](size_t m) {
        const Id id = boundary[m];
        grid.points[id] = place_on_surface(body, centre, grid.points[id] - centre, h);
        grid.kinds[id] = VertexKind::slip;
    });
    fill_interior_tfi(block, grid.points);
    grid.blocks.push_back(std::move(block));
    return grid;
}

}  // namespace hexmesh

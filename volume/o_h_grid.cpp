#include "volume/o_h_grid.h"

#include <array>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>
#include <tbb/parallel_for.h>

#include "volume/surface_placement.h"
#include "volume/tfi.h"

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;

// One wall block per cube face: the outward axis, its side, and the two in-face axes taken
// as (i, j) so that (i, j, outward) is right-handed.
struct WallFace {
    const char* name;
    int axis;
    bool max_side;
    int axis_i, axis_j;
};
constexpr std::array<WallFace, 6> wall_faces = {{
    {"wall_xmin", 0, false, 2, 1},
    {"wall_xmax", 0, true, 1, 2},
    {"wall_ymin", 1, false, 0, 2},
    {"wall_ymax", 1, true, 2, 0},
    {"wall_zmin", 2, false, 1, 0},
    {"wall_zmax", 2, true, 0, 1},
}};

void check_options(const OHGridOptions& o) {
    if (o.cells_per_edge < 2) throw std::invalid_argument("cells_per_edge must be at least 2");
    if (o.wall_cells < 1) throw std::invalid_argument("wall_cells must be at least 1");
    if (!(o.core_size > 0 && o.core_size < 1))
        throw std::invalid_argument("core_size must be in (0, 1)");
}

}  // namespace

double grid_length_scale(const ImplicitFunction& body, int cells_per_edge) {
    return body.bounds().diagonal() / (std::sqrt(3.0) * cells_per_edge);
}

BlockGrid make_o_h_grid(const ImplicitFunction& body, const OHGridOptions& options) {
    check_options(options);
    const int n = options.cells_per_edge, nk = options.wall_cells;
    const Box3 box = body.bounds();
    const Vec3 centre = options.centre.value_or(box.center());
    const Vec3 half = 0.5 * box.size();
    const double h = grid_length_scale(body, n);
    require_inside(body, centre);

    // Lattice (a,b,c) in [0,n]^3: the core's nodes. Its boundary points double as the
    // wall-patch lattice; surface_index numbers them for the wall layers 1..nk.
    const Dims lattice{n + 1, n + 1, n + 1};
    std::vector<Id> surface_index(lattice.count(), -1);
    std::vector<std::array<int, 3>> surface_points;
    for (int c = 0; c <= n; ++c)
        for (int b = 0; b <= n; ++b)
            for (int a = 0; a <= n; ++a)
                if (a == 0 || a == n || b == 0 || b == n || c == 0 || c == n) {
                    surface_index[lattice.flat(a, b, c)] = Id(surface_points.size());
                    surface_points.push_back({a, b, c});
                }
    const Id ns = Id(surface_points.size());
    auto node_id = [&](const std::array<int, 3>& abc, int layer) {
        const Id core = lattice.flat(abc[0], abc[1], abc[2]);
        return layer == 0 ? core : lattice.count() + (layer - 1) * ns + surface_index[core];
    };

    // Equiangular cube-sphere coordinate: rays through the core nodes are evenly spread.
    auto ray = [&](const std::array<int, 3>& abc) {
        Vec3 w;
        for (int d = 0; d < 3; ++d) w[d] = half[d] * std::tan(pi / 4 * (2.0 * abc[d] / n - 1));
        return w;
    };

    BlockGrid grid;
    grid.points.assign(lattice.count() + nk * ns, Vec3::Zero());
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    for (const auto& abc : surface_points)
        grid.points[node_id(abc, 0)] = centre + options.core_size * ray(abc);

    tbb::parallel_for(Id(0), ns, [&](Id s) {
        const auto& abc = surface_points[s];
        const Vec3 dir = ray(abc);
        const Vec3 wall = place_on_surface(body, centre, dir, h);
        const Vec3 core = grid.points[node_id(abc, 0)];
        const double length = (wall - core).norm();
        if ((wall - core).dot(dir) <= 0) {
            throw std::invalid_argument(fmt::format(
                "core_size {} puts the core box outside the body near ({:.4g}, {:.4g}, "
                "{:.4g}); use a smaller core_size",
                options.core_size, core.x(), core.y(), core.z()));
        }
        const std::vector<double> d = wall_distances(length, nk, options.wall_layers);
        for (int layer = 1; layer <= nk; ++layer)
            grid.points[node_id(abc, layer)] = wall + (core - wall) * (d[nk - layer] / length);
        grid.kinds[node_id(abc, nk)] = VertexKind::slip;
    });

    Block core{"core", lattice, {}, {}};
    core.node_ids.resize(lattice.count());
    for (Id id = 0; id < lattice.count(); ++id) core.node_ids[id] = id;
    fill_interior_tfi(core, grid.points);
    grid.blocks.push_back(std::move(core));

    for (const WallFace& f : wall_faces) {
        Block b{f.name, {n + 1, n + 1, nk + 1}, {}, {}};
        b.face_patch[kmax] = "wall";
        b.node_ids.resize(b.nodes.count());
        for (int k = 0; k <= nk; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    std::array<int, 3> abc;
                    abc[f.axis] = f.max_side ? n : 0;
                    abc[f.axis_i] = i;
                    abc[f.axis_j] = j;
                    b.node_ids[b.nodes.flat(i, j, k)] = node_id(abc, k);
                }
        grid.blocks.push_back(std::move(b));
    }
    return grid;
}

}  // namespace hexmesh

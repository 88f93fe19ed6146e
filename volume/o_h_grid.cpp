#include "volume/o_h_grid.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "surface/implicit_features.h"
#include "volume/cube_sphere.h"
#include "volume/feature_snapping.h"
#include "volume/surface_placement.h"
#include "volume/tfi.h"

namespace hexmesh {
namespace {

void check_options(const OHGridOptions& o) {
    if (o.cells_per_edge < 2) throw std::invalid_argument("cells_per_edge must be at least 2");
    if (o.wall_cells < 1) throw std::invalid_argument("wall_cells must be at least 1");
    if (!(o.core_size > 0 && o.core_size < 1))
        throw std::invalid_argument("core_size must be in (0, 1)");
}

// The body's corners `found` as the cube's, when there is exactly one in each octant around
// the centre; nullopt otherwise.
std::optional<CubeCorners> body_corners_by_octant(const Vec3& centre,
                                                  const std::vector<Vec3>& found, double h) {
    if (found.size() != 8) return std::nullopt;
    CubeCorners corners;
    std::array<bool, 8> taken{};
    for (const Vec3& c : found) {
        const Vec3 r = c - centre;
        if ((r.cwiseAbs().array() < 1e-3 * h).any()) return std::nullopt;  // on an axis plane
        const int octant = (r.x() > 0) + 2 * (r.y() > 0) + 4 * (r.z() > 0);
        if (taken[octant]) return std::nullopt;
        taken[octant] = true;
        corners[octant] = r;
    }
    return corners;
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
    // wall-patch lattice, numbered for the wall layers 1..nk.
    const CubeSurfaceLattice surface = make_cube_surface_lattice(n);
    const Dims lattice = surface.lattice;
    const Id ns = surface.size();
    auto node_id = [&](const LatticePoint& abc, int layer) {
        const Id core = lattice.flat(abc[0], abc[1], abc[2]);
        return layer == 0 ? core : lattice.count() + (layer - 1) * ns + surface.number[core];
    };
    if (options.wall_from && Id(options.wall_from->size()) != lattice.count() + nk * ns)
        throw std::invalid_argument("wall_from: the points of a grid made with other options");

    // The wall nodes: given, or the radial projections of the rays through the bounds' box,
    // then (box-like bodies) through the body's corners.
    std::optional<CubeCorners> corners;
    auto ray = [&](const LatticePoint& abc) {
        return corners ? cube_sphere_ray(abc, n, *corners) : cube_sphere_ray(abc, n, half);
    };
    std::vector<Vec3> wall(ns);
    const auto place_wall = [&] {
        tbb::parallel_for(Id(0), ns, [&](Id s) {
            const LatticePoint& abc = surface.points[s];
            wall[s] = options.wall_from ? (*options.wall_from)[node_id(abc, nk)]
                                        : place_on_surface(body, centre, ray(abc), h);
        });
    };
    place_wall();
    if (options.patch_corners_on_body_corners && !options.wall_from) {
        corners = body_corners_by_octant(centre, body_corners_near(body, wall, h), h);
        if (corners) place_wall();
    } else if (options.patch_corners_on_body_corners) {
        // A given wall keeps the choice of the grid it came from: its 8 patch-corner nodes sit
        // on body corners, one per octant, exactly when that grid's rays spanned them.
        std::vector<Vec3> at_corners;
        for (int c = 0; c < 8; ++c) {
            const LatticePoint abc = {(c & 1) * n, (c >> 1 & 1) * n, (c >> 2 & 1) * n};
            const Vec3& x = wall[surface.number_of(abc)];
            if (classify_surface_point(body, x, 1e-6 * h) == FeatureKind::corner)
                at_corners.push_back(x);
        }
        corners = body_corners_by_octant(centre, at_corners, h);
    }

    BlockGrid grid;
    grid.points.assign(lattice.count() + nk * ns, Vec3::Zero());
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    for (const LatticePoint& abc : surface.points)
        grid.points[node_id(abc, 0)] = centre + options.core_size * ray(abc);

    tbb::parallel_for(Id(0), ns, [&](Id s) {
        const LatticePoint& abc = surface.points[s];
        const Vec3 dir = ray(abc);
        const Vec3 wall_node = wall[s];
        const Vec3 core = grid.points[node_id(abc, 0)];
        const double length = (wall_node - core).norm();
        if ((wall_node - core).dot(dir) <= 0 && options.wall_from) {
            throw std::invalid_argument(fmt::format(
                "the given wall node at ({:.4g}, {:.4g}, {:.4g}) lies behind its core node: its "
                "line would turn back",
                wall_node.x(), wall_node.y(), wall_node.z()));
        }
        if ((wall_node - core).dot(dir) <= 0) {
            throw std::invalid_argument(fmt::format(
                "core_size {} puts the core box outside the body near ({:.4g}, {:.4g}, "
                "{:.4g}); use a smaller core_size",
                options.core_size, core.x(), core.y(), core.z()));
        }
        const std::vector<double> d = wall_distances(length, nk, options.wall_layers);
        for (int layer = 1; layer <= nk; ++layer)
            grid.points[node_id(abc, layer)] =
                wall_node + (core - wall_node) * (d[nk - layer] / length);
        grid.kinds[node_id(abc, nk)] = VertexKind::slip;
    });

    Block core{"core", lattice, {}, {}};
    core.node_ids.resize(lattice.count());
    for (Id id = 0; id < lattice.count(); ++id) core.node_ids[id] = id;
    fill_interior_tfi(core, grid.points);
    grid.blocks.push_back(std::move(core));

    for (const CubePatch& patch : cube_patches) {
        Block b{std::string("wall_") + patch.side, {n + 1, n + 1, nk + 1}, {}, {}};
        b.face_patch[kmax] = "wall";
        b.node_ids.resize(b.nodes.count());
        for (int k = 0; k <= nk; ++k)
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i)
                    b.node_ids[b.nodes.flat(i, j, k)] =
                        node_id(surface.patch_point(patch, i, j), k);
        grid.blocks.push_back(std::move(b));
    }
    return grid;
}

}  // namespace hexmesh

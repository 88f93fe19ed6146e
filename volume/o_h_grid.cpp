// make_o_h_grid: the O-H grid laid out step by step (core, wall, rays, fitted rings, wall
// layers, blocks), and the core size that fits inside its wall.
#include "volume/o_h_grid.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "hexmesh/core/deterministic_for.h"
#include "surface/implicit_features.h"
#include "volume/axial_creases.h"
#include "volume/axial_rings.h"
#include "volume/core_layout.h"
#include "volume/cube_sphere.h"
#include "volume/feature_snapping.h"
#include "volume/path_lines.h"
#include "volume/surface_placement.h"
#include "volume/tfi.h"
#include "volume/wall_lines.h"

namespace hexmesh {
namespace {

void check_options(const OHGridOptions& o) {
    if (o.cells_per_edge < 2) throw std::invalid_argument("cells_per_edge must be at least 2");
    if (o.wall_cells < 1) throw std::invalid_argument("wall_cells must be at least 1");
    if (!(o.core_size > 0 && o.core_size < 1))
        throw std::invalid_argument("core_size must be in (0, 1)");
    if (o.axis < -1 || o.axis > 2) throw std::invalid_argument("axis must be -1, 0, 1 or 2");
    if (o.ring_cells < 0) throw std::invalid_argument("ring_cells must be 0 or more");
    if (o.frame_cells < 0 || (o.axis >= 0 && 2 * o.frame_cells >= o.cells_per_edge))
        throw std::invalid_argument("frame_cells must be 0 or more and under half cells_per_edge");
}

// The core node at cube corner c (entry (a > 0) + 2 (b > 0) + 4 (c > 0) as CubeCorners):
// the wall node furthest towards it.
Id cube_corner_node(const CoreLayout& core, const std::vector<Id>& on_wall, int c) {
    const Vec3 towards(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
    return *std::max_element(on_wall.begin(), on_wall.end(), [&](Id x, Id y) {
        return core.t[x].dot(towards) < core.t[y].dot(towards);
    });
}

// The wall block on a core wall face: "wall_<side>", or "wall_<side>_<piece>" for a piece of
// a split side, with (i, j) the face's index directions ordered so that (i, j, outward) is
// right-handed, k = 0 on the core and k = nk on the wall; node_id(core id, layer).
template <class NodeId>
Block wall_block(const Block& base, const CoreLayout::WallFace& f, const std::vector<Vec3>& t,
                 int nk, NodeId&& node_id) {
    const CubePatch& patch = cube_patches[f.side];
    const WallFace face = block_face(base, f.face);
    const int np = face.np, nq = face.nq;
    const Vec3 origin = t[face.node(0, 0, 0)];
    const Vec3 along_p = t[face.node(1, 0, 0)] - origin;
    const Vec3 along_q = t[face.node(0, 1, 0)] - origin;
    const Vec3 outward = (patch.max_side ? 1.0 : -1.0) * Vec3::Unit(patch.axis);
    const bool swap = along_p.cross(along_q).dot(outward) < 0;
    const std::string piece = base.name.size() > 5 ? base.name.substr(5) : "";
    const std::string side = patch.side;
    const bool whole_side = piece.empty() || piece == "ring_" + side || piece == "frame_" + side;
    Block b{"wall_" + side + (whole_side ? "" : "_" + piece),
            {swap ? nq : np, swap ? np : nq, nk + 1},
            {},
            {}};
    b.face_patch[kmax] = "wall";
    b.node_ids.resize(b.nodes.count());
    for (int k = 0; k <= nk; ++k)
        for (int j = 0; j < b.nodes.nj; ++j)
            for (int i = 0; i < b.nodes.ni; ++i)
                b.node_ids[b.nodes.flat(i, j, k)] =
                    node_id(swap ? face.node(j, i, 0) : face.node(i, j, 0), k);
    return b;
}

// The core nodes on its wall faces, in core order (on_wall), and each core node's number
// among them (-1 inside the core).
void number_wall_nodes(const CoreLayout& core, std::vector<Id>& number, std::vector<Id>& on_wall) {
    number.assign(core.t.size(), -1);
    on_wall.clear();
    for (const CoreLayout::WallFace& f : core.wall_faces) {
        const WallFace face = block_face(core.blocks[f.block], f.face);
        for (int q = 0; q < face.nq; ++q)
            for (int p = 0; p < face.np; ++p) number[face.node(p, q, 0)] = 0;
    }
    for (Id id = 0; id < Id(core.t.size()); ++id)
        if (number[id] == 0) number[id] = Id(on_wall.size()), on_wall.push_back(id);
}

}  // namespace

int choose_o_h_axis(const ImplicitFunction& body, const OHGridOptions& options) {
    check_options(options);
    const int n = options.cells_per_edge;
    if (2 * options.frame_cells >= n) return -1;  // no room for an axial core
    const Vec3 centre = options.centre.value_or(body.bounds().center());
    const Vec3 half = 0.5 * body.bounds().size();
    const double h = grid_length_scale(body, n);
    require_inside(body, centre);
    // The box-like body's corners, if any, as the grid finds them, from a wall of at most 16
    // cells per edge (its nodes' reach grows as they thin out): only the rays' frame matters here.
    const int coarse = std::min(n, 16);
    const CoreLayout core = one_block_core(coarse);
    std::vector<Id> number, on_wall;
    number_wall_nodes(core, number, on_wall);
    std::optional<CubeCorners> corners;
    if (options.patch_corners_on_body_corners) {
        const double coarse_h = grid_length_scale(body, coarse);
        std::vector<Vec3> wall(on_wall.size());
        tbb::parallel_for(size_t(0), wall.size(), [&](size_t s) {
            wall[s] = place_on_surface(body, centre, cube_ray(core.t[on_wall[s]], half), coarse_h);
        });
        corners = corners_near_wall(body, centre, wall, coarse_h);
    }
    auto ray = [&](const Vec3& t) { return corners ? cube_ray(t, *corners) : cube_ray(t, half); };
    std::array<AxialCreases, 3> creases;
    tbb::parallel_for(0, 3, [&](int axis) {
        creases[axis] = find_axial_creases(body, centre, ray, axis,
                                           axial_frame_edge(n, options.frame_cells), h);
    });
    return choose_axis(creases);
}

double grid_length_scale(const ImplicitFunction& body, int cells_per_edge) {
    return body.bounds().diagonal() / (std::sqrt(3.0) * cells_per_edge);
}

namespace {

// An O-H grid as it is laid out: its core in cube coordinates, where the core's nodes go
// (inner_t), the core's nodes on the cube's surface, numbered in core order, which double as
// the wall patches' nodes of the wall layers 1..nk, the wall points, and the rays' frame.
struct OHLayout {
    CoreLayout core;
    std::vector<Vec3> inner_t;
    Id core_nodes = 0;
    std::vector<Id> number, on_wall;  // surface number of each core node; its core node
    Id ns = 0;                        // nodes on the wall
    int nk = 0;                       // wall layers
    std::vector<Vec3> wall;
    Vec3 half;  // of the bounds' box
    std::optional<CubeCorners> corners;

    // The ray through cube coordinates t: through the bounds' box, or the body's corners.
    Vec3 ray(const Vec3& t) const { return corners ? cube_ray(t, *corners) : cube_ray(t, half); }
    // The grid's id of a core node's copy in wall layer `layer` (0: the core node).
    Id node_id(Id core_id, int layer) const {
        return layer == 0 ? core_id : core_nodes + (layer - 1) * ns + number[core_id];
    }
};

// The core (one block, or the axial core over even rings) and its wall nodes' numbering.
OHLayout lay_out_core(const OHGridOptions& options, const Vec3& half, int ring_cells,
                      double ring_edge) {
    const int n = options.cells_per_edge;
    OHLayout lay;
    lay.core = options.axis < 0 ? one_block_core(n)
                                : axial_core(n, options.frame_cells,
                                             even_axial_rings(options.axis, ring_cells, ring_edge));
    lay.inner_t = lay.core.t;  // where the core's nodes go: see o_h_grid
    lay.core_nodes = Id(lay.core.t.size());
    number_wall_nodes(lay.core, lay.number, lay.on_wall);
    lay.ns = Id(lay.on_wall.size());
    lay.nk = options.wall_cells;
    lay.half = half;
    if (options.wall_from && Id(options.wall_from->size()) != lay.core_nodes + lay.nk * lay.ns)
        throw std::invalid_argument("wall_from: the points of a grid made with other options");
    return lay;
}

// The wall nodes: given (wall_from, wall_nodes), or the rays placed on the body.
void place_wall(OHLayout& lay, const ImplicitFunction& body, const OHGridOptions& options,
                const Vec3& centre, double h) {
    lay.wall.resize(size_t(lay.ns));
    tbb::parallel_for(Id(0), lay.ns, [&](Id s) {
        lay.wall[s] = options.wall_from ? (*options.wall_from)[lay.node_id(lay.on_wall[s], lay.nk)]
                      : options.wall_nodes
                          ? (*options.wall_nodes)[s]
                          : place_on_surface(body, centre, lay.ray(lay.core.t[lay.on_wall[s]]), h);
    });
}

// The rays' frame of a box-like body: through its corners near the wall's, or, for a given
// wall, those its patch-corner nodes sit on; none for a wall placed without rays.
void choose_ray_frame(OHLayout& lay, const ImplicitFunction& body, const OHGridOptions& options,
                      const Vec3& centre, double h, bool placed) {
    if (placed) {
        // No ray frame: the core is a box of the given half extents.
    } else if (options.patch_corners_on_body_corners && !options.wall_from) {
        lay.corners = corners_near_wall(body, centre, lay.wall, h);
    } else if (options.patch_corners_on_body_corners) {
        // A given wall keeps the choice of the grid it came from: its 8 patch-corner nodes sit
        // on body corners exactly when that grid's rays spanned them, and they are those.
        std::array<Vec3, 8> at;
        for (int c = 0; c < 8; ++c)
            at[c] = lay.wall[lay.number[cube_corner_node(lay.core, lay.on_wall, c)]];
        lay.corners = corners_at_patch_corners(body, centre, at, h);
    }
}

// The axial core over rings fitted to the body's creases around the axis.
void fit_core_rings(OHLayout& lay, const ImplicitFunction& body, const OHGridOptions& options,
                    const Vec3& centre, double h, int ring_cells, double ring_edge) {
    const auto ray = [&](const Vec3& t) { return lay.ray(t); };
    lay.core = axial_core(
        options.cells_per_edge, options.frame_cells,
        fit_axial_rings(find_axial_creases(body, centre, ray, options.axis, ring_edge, h),
                        options.axis, ring_cells, ring_edge));
    if (Id(lay.core.t.size()) != lay.core_nodes)
        throw std::logic_error("axial core: the fitted rings changed the core's node count");
}

// The core size that keeps the core inside the wall (see core_size_within_wall): node s of the
// core lies at centre + core_size dir, inside while core_size is below
// (wall - centre) . dir / |dir|^2.
double fit_core_size(const OHLayout& lay, const OHGridOptions& options, const Vec3& centre,
                     bool placed) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Id s = 0; s < lay.ns && !placed; ++s) {
        const Vec3 dir = lay.ray(lay.inner_t[lay.on_wall[s]]);
        nearest = std::min(nearest, (lay.wall[s] - centre).dot(dir) / dir.squaredNorm());
    }
    return options.core_size > 0.9 * nearest ? 0.5 * nearest : options.core_size;
}

// The wall lines along `paths` (place_nodes_on_paths), on from each path's end to its core
// node, whose point is set. A path left as its wall point alone, or with no room for the
// boundary layer and a cell beyond it (a wall next to the potential's source), is replaced by
// the straight segment from its wall node towards its core node, halfway (0.95 of the way when
// the layer and a cell do not fit halfway), its level rising evenly to the far level: the line
// runs straight to the core.
// Throws std::invalid_argument, naming the wall point, when the whole layer does not fit a line
// (path and segment): the paths lay the same layers on every line, so a line where the body is
// thin cannot take fewer as the straight construction's do.
void place_on_paths(const OHLayout& lay, WallPaths paths, const WallLayers& law, BlockGrid& grid) {
    const int nk = lay.nk;
    if (Id(paths.lines.size()) != lay.ns || Id(paths.levels.size()) != lay.ns)
        throw std::invalid_argument("paths: one per wall node expected");
    std::vector<Vec3> core(size_t(lay.ns));
    const double room =  // the boundary layer and one cell more beyond it
        law.layers > 0
            ? layers_thickness(law) + law.first_height * std::pow(law.growth_ratio, law.layers)
            : 0.0;
    for (Id s = 0; s < lay.ns; ++s) {
        core[s] = grid.points[lay.on_wall[s]];
        const std::vector<Vec3>& x = paths.lines[s];
        double length = 0;
        for (size_t k = 1; k < x.size(); ++k) length += (x[k] - x[k - 1]).norm();
        require_whole_layers(length + (core[s] - x.back()).norm(), nk, law, &lay.wall[s]);
        if (x.size() >= 2 && length > room) continue;
        const bool halfway = room < 0.5 * (core[s] - lay.wall[s]).norm();
        paths.lines[s] = {lay.wall[s], halfway
                                           ? Vec3(0.5 * (lay.wall[s] + core[s]))
                                           : Vec3(lay.wall[s] + 0.95 * (core[s] - lay.wall[s]))};
        paths.levels[s] = {0.0, paths.far_level};
    }
    place_nodes_on_paths(paths, lay.wall, core, nk, law, [&](Id s, const std::vector<Vec3>& x) {
        const Id core_id = lay.on_wall[s];
        for (int k = 0; k < nk; ++k) grid.points[lay.node_id(core_id, nk - k)] = x[k];
        grid.kinds[lay.node_id(core_id, nk)] = VertexKind::slip;
    });
}

// The grid's points: the core's nodes, then along each wall node's line to its core node the
// wall layers graded by the law (the last on the wall, a slip node), or with `paths` as
// place_on_paths lays them. A line too short for the whole layer takes the layers that fit it
// (layers_that_fit). Throws std::invalid_argument when a line would turn back or is too short
// for even the first layer (the first such line in wall order).
BlockGrid place_points(const OHLayout& lay, const OHGridOptions& options, const Vec3& centre,
                       bool placed, const WallPaths* paths) {
    const int nk = lay.nk;
    BlockGrid grid;
    grid.points.assign(lay.core_nodes + nk * lay.ns, Vec3::Zero());
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    for (Id id = 0; id < lay.core_nodes; ++id)
        grid.points[id] = options.core_half
                              ? Vec3(centre + options.core_half->cwiseProduct(lay.inner_t[id]))
                              : Vec3(centre + options.core_size * lay.ray(lay.inner_t[id]));

    if (paths) {
        place_on_paths(lay, *paths, options.wall_layers, grid);
        return grid;
    }
    deterministic_for(lay.ns, [&](Id s) {
        const Id core_id = lay.on_wall[s];
        const Vec3 dir = lay.ray(lay.inner_t[core_id]);
        const Vec3 wall_node = lay.wall[s];
        const Vec3 inner = grid.points[core_id];
        const double length = (wall_node - inner).norm();
        if ((wall_node - inner).dot(dir) <= 0 && options.wall_from && !placed) {
            throw std::invalid_argument(fmt::format(
                "the given wall node at ({:.4g}, {:.4g}, {:.4g}) lies behind its core node: its "
                "line would turn back",
                wall_node.x(), wall_node.y(), wall_node.z()));
        }
        if ((wall_node - inner).dot(dir) <= 0 && !placed) {
            throw std::invalid_argument(
                fmt::format("core_size {} puts the core box outside the body near ({:.4g}, {:.4g}, "
                            "{:.4g}); use a smaller core_size",
                            options.core_size, inner.x(), inner.y(), inner.z()));
        }
        const std::vector<double> d = wall_distances(length, nk, options.wall_layers, &wall_node);
        for (int layer = 1; layer <= nk; ++layer)
            grid.points[lay.node_id(core_id, layer)] =
                wall_node + (inner - wall_node) * (d[nk - layer] / length);
        grid.kinds[lay.node_id(core_id, nk)] = VertexKind::slip;
    });
    return grid;
}

// The core's blocks, interiors filled by TFI, then the wall blocks, cube side by cube side.
void add_blocks(BlockGrid& grid, OHLayout& lay) {
    for (Block& block : lay.core.blocks) {
        fill_interior_tfi(block, grid.points);
        grid.blocks.push_back(std::move(block));
    }
    const auto node_id = [&](Id core_id, int layer) { return lay.node_id(core_id, layer); };
    for (int side = 0; side < 6; ++side)
        for (const CoreLayout::WallFace& f : lay.core.wall_faces) {
            if (f.side != side) continue;
            const Block& base = grid.blocks[f.block];
            grid.blocks.push_back(wall_block(base, f, lay.core.t, lay.nk, node_id));
        }
}

// make_o_h_grid; with `fitted_core_size`, only its wall and rays are laid out and the core
// size that fits them (core_size_within_wall) is written there, the grid left empty.
BlockGrid o_h_grid(const ImplicitFunction& body, const OHGridOptions& options,
                   double* fitted_core_size) {
    check_options(options);
    const int n = options.cells_per_edge;
    const Box3 box = body.bounds();
    const Vec3 centre = options.centre.value_or(box.center());
    const double h = grid_length_scale(body, n);
    require_inside(body, centre);

    const int ring_cells = options.ring_cells > 0 ? options.ring_cells : (n + 1) / 2;
    const double ring_edge = axial_frame_edge(n, options.frame_cells);
    OHLayout lay = lay_out_core(options, 0.5 * box.size(), ring_cells, ring_edge);

    // The wall nodes: given, or the radial projections of the rays through the bounds' box,
    // then (box-like bodies) through the body's corners.
    const bool placed = options.wall_nodes || options.core_half;  // the wall is not radial
    if (placed && options.axis >= 0)
        throw std::invalid_argument("a wall placed without rays takes one core block (axis -1)");
    if (options.wall_nodes && Id(options.wall_nodes->size()) != lay.ns)
        throw std::invalid_argument("wall_nodes: a lattice of another size");
    place_wall(lay, body, options, centre, h);
    choose_ray_frame(lay, body, options, centre, h, placed);
    if (options.axis >= 0) fit_core_rings(lay, body, options, centre, h, ring_cells, ring_edge);
    if ((lay.corners || options.axis >= 0) && !options.wall_from)
        place_wall(lay, body, options, centre, h);
    // The wall follows the fitted rings; the core lies halfway between them and even rings.
    // On the fitted rings alone the core's column is as thin as half the first crease, and
    // its needle cells can buckle under the optimizer (box with cylinder, 48 cells per edge:
    // min scaled Jacobian 0.04, against 0.36 halfway); halfway keeps the lines near radial.
    if (options.axis >= 0)
        for (Id id = 0; id < lay.core_nodes; ++id)
            lay.inner_t[id] = 0.5 * (lay.inner_t[id] + lay.core.t[id]);

    if (fitted_core_size) {
        *fitted_core_size = fit_core_size(lay, options, centre, placed);
        return {};
    }
    std::optional<WallPaths> paths;
    if (placed && options.paths && lay.nk >= 2) paths = options.paths(lay.wall);
    BlockGrid grid = place_points(lay, options, centre, placed, paths ? &*paths : nullptr);
    add_blocks(grid, lay);
    return grid;
}

}  // namespace

BlockGrid make_o_h_grid(const ImplicitFunction& body, const OHGridOptions& options) {
    return o_h_grid(body, options, nullptr);
}

double core_size_within_wall(const ImplicitFunction& body, const OHGridOptions& options) {
    double fitted = options.core_size;
    o_h_grid(body, options, &fitted);
    return fitted;
}

}  // namespace hexmesh

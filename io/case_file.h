// Case files: the JSON a user writes to describe a run, parsed and validated into plain structs.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hexmesh/core/far_field_shape.h"
#include "hexmesh/core/types.h"
#include "io/flow_spec.h"
#include "io/input_error.h"

namespace hexmesh {

// The choices a case file names by words; each enum's values are in the order of its names
// (E(i) is names[i]), and name_of gives the word back.
enum class Domain { interior, exterior };  // the grid inside the body, or around it
inline constexpr std::array<const char*, 2> domain_names = {"interior", "exterior"};
enum class Topology { o_h, single_block };
inline constexpr std::array<const char*, 2> topology_names = {"o-h", "single-block"};
// An O-H grid's axis: automatic (around the axis the body's creases run around, if any),
// none (one core block), or x, y, z (the core and the patches across it O-gridded around it).
enum class GridAxis { none, automatic, x, y, z };
inline constexpr std::array<const char*, 5> axis_names = {"none", "auto", "x", "y", "z"};
inline constexpr std::array<const char*, 2> far_field_shape_names = {"sphere", "box"};
// What a geometry node is: a primitive, a file (a surface, a point cloud, a stack of cross
// sections) or a CSG operation over children.
enum class BodyKind {
    sphere,
    ellipsoid,
    box,
    cylinder,
    torus,
    cone,
    file,
    points,
    sections,
    csg_union,
    csg_intersection,
    csg_difference
};
inline constexpr std::array<const char*, 12> body_kind_names = {
    "sphere", "ellipsoid", "box",      "cylinder", "torus",        "cone",
    "file",   "points",    "sections", "union",    "intersection", "difference"};

inline const char* name_of(Domain d) {
    return domain_names[std::size_t(d)];
}
inline const char* name_of(Topology t) {
    return topology_names[std::size_t(t)];
}
inline const char* name_of(GridAxis a) {
    return axis_names[std::size_t(a)];
}
inline const char* name_of(FarFieldShape s) {
    return far_field_shape_names[std::size_t(s)];
}
inline const char* name_of(BodyKind k) {
    return body_kind_names[std::size_t(k)];
}

// The axis index 0, 1, 2 of x, y, z; -1 for none and automatic.
inline int axis_index(GridAxis a) {
    return a == GridAxis::x ? 0 : a == GridAxis::y ? 1 : a == GridAxis::z ? 2 : -1;
}
// A body read from a file (surface, points, sections), or a CSG operation.
inline bool is_file_body(BodyKind k) {
    return k == BodyKind::file || k == BodyKind::points || k == BodyKind::sections;
}
inline bool is_csg(BodyKind k) {
    return k >= BodyKind::csg_union;
}

// A body as written in the case: a primitive, or a CSG node over children, with an
// optional transform (applied as scale, then rotate, then translate).
struct GeometrySpec {
    BodyKind kind = BodyKind::sphere;
    Vec3 center = Vec3::Zero();
    double radius = 0;                          // sphere, cylinder
    Vec3 semi_axes = Vec3::Zero();              // ellipsoid
    Vec3 size = Vec3::Zero();                   // box: full edge lengths
    double height = 0;                          // cylinder, cone: full height along z
    double major_radius = 0, minor_radius = 0;  // torus in the xy plane
    double bottom_radius = 0, top_radius = 0;   // cone (frustum), bottom at lower z
    std::vector<GeometrySpec> children;         // CSG operands, in order
    // file: surface (STL OBJ OFF PLY); points: oriented point cloud (PLY XYZ); sections: a
    // cross-section stack (io/sample_readers.h). Resolved against the case's folder.
    std::string file;
    double voxel_size = 0;      // file: voxel of its signed distance field (0: longest side / 256)
    double feature_angle = 30;  // file: edges turning more than this are sharp creases (degrees)
    Vec3 translate = Vec3::Zero();
    Vec3 rotate_axis = Vec3::UnitZ();
    double rotate_degrees = 0;
    double scale = 1;
};

struct GridSpec {
    Topology topology = Topology::o_h;  // single_block: interior domain only
    int cells_per_edge = 20;            // o-h, o-grid: cells along each core/patch edge
    double cell_size = 0;               // > 0: cells_per_edge from the body's size instead
    // o-h: cells from the core to the wall; o-grid: to the far field (default twice
    // cells_per_edge for an exterior domain)
    int wall_cells = 10;
    bool wall_cells_given = false;
    double core_size = 0.45;       // o-h: core half-size / body half extents
    bool core_size_given = false;  // else smaller when 0.45 would reach the wall (build_blocks)
    std::array<int, 3> cells = {20, 20, 20};  // single-block
    std::optional<Vec3> center;
    GridAxis axis = GridAxis::automatic;  // o-h only
    int ring_cells = 0;                   // o-h with an axis: cells across the rings (0: (n+1)/2)
    int frame_cells = 1;  // o-h with an axis: cells across the frame along the edges
};

// The boundary layer: first_height given, or estimated from a target y+ by the flat-plate
// skin-friction correlation (see first_height_from_y_plus).
struct BoundaryLayerSpec {
    double first_height = 0;  // geometry units
    double growth_ratio = 1;
    int layers = 0;
    double y_plus = 0;    // > 0 when first_height was derived from y+
    double reynolds = 0;  // Reynolds number of the y+ estimate
};

// The far-field boundary of an exterior grid: a sphere of radius `size` or a cube of
// half-size `size`, centred on the grid centre (size 0: 10 body radii).
struct FarFieldSpec {
    FarFieldShape shape = FarFieldShape::sphere;
    double size = 0;
};

// The variational optimizer (docs/architecture.md#the-functional, #boundary-conditions, #solvers),
// per phase: `untangle` while some cell is inverted, `optimize` (pure barrier) afterwards.
struct SolverSpec {
    std::string untangle = "newton-cg";
    std::string optimize = "newton-cg";
    // Volume weight of the functional while optimizing. Below the paper's 0.8
    // (docs/architecture.md#the-functional): weighing shape more gives better wall-layer grids
    // (README, "solver"; bench/RESULTS.md).
    double theta = 0.2;
    int max_iterations = 200;      // untangling outer iterations
    int optimize_iterations = 10;  // barrier outer iterations; 0 keeps the constructed grid
    // Barrier outer iterations of the surface pass (the wall grid alone on u = 0 with the 2D
    // functional, before the volume); 0 skips it.
    int surface_iterations = 10;
    // Weight of the term that holds the wall quads to the body between their nodes in the
    // surface pass, the joint optimization and the polish (hexmesh/pipeline/corner_tets.h:
    // hold_wall_quads): a quad whose centre lies one wall cell off the body costs this many
    // times its cell's best shape energy. 0 (the default) lets wall nodes slide wherever the
    // cells are best (bench/RESULTS.md, "Wall quads held to the body").
    double wall_fidelity = 0;
};

// A nested grid-convergence family: `run` writes levels 1..levels, each level the one before
// with every cell split into 8 (hexmesh/pipeline/refine.h). 1: the grid alone.
struct RefinementSpec {
    int levels = 1;  // 1..5
};

// A tetrahedral mesh of the body's interior (`hexmesh tetmesh`): edge lengths follow
// h(x) = min(cell_size, wall_cell_size + grading |u(x)|), fine at the wall, coarser inside.
struct TetMeshSpec {
    double cell_size = 0;       // 0: grid.cell_size if given, else the body's diagonal / 30
    double wall_cell_size = 0;  // 0: cell_size everywhere
    double grading = 0.5;       // growth of the size per unit distance from the wall
    double facet_distance = 0;  // 0: a tenth of the wall cell size
    double feature_angle = 30;  // surface files: edges turning more than this are creases (degrees)
};

struct Case {
    std::string path;  // the file it came from, for messages
    GeometrySpec geometry;
    Domain domain = Domain::interior;
    GridSpec grid;
    FarFieldSpec far_field;  // exterior only
    std::optional<BoundaryLayerSpec> boundary_layer;
    SolverSpec solver;
    std::vector<std::string> outputs = {"vtk"};
    RefinementSpec refinement;
    TetMeshSpec tet_mesh;
    FlowSpec flow;  // what the OpenFOAM output's fields and dictionaries are set up for
};

// Height of the first cell for a target y+ on a flat plate of length L = reynolds * viscosity /
// (density * velocity): Cf = 0.026 Re^(-1/7), tau_w = Cf rho U^2 / 2, u_tau = sqrt(tau_w / rho),
// y = y+ mu / (rho u_tau) (the turbulent flat-plate estimate of White, Fluid Mechanics).
double first_height_from_y_plus(double y_plus, double reynolds, double velocity, double density,
                                double viscosity);

// Reads and validates a case file. Unknown keys, wrong types and out-of-range values throw
// InputError naming the key path (e.g. "grid.cells_per_edge") and the expected value.
Case read_case(const std::string& path);

// Same, from JSON text; `path` only labels messages.
Case parse_case(const std::string& text, const std::string& path);

// The case as JSON text that parse_case reads back to the same geometry, domain, grid, far
// field, boundary layer (first_height, also when it came from y+) and solver; surface file
// paths absolute, so the text is valid wherever it is stored (the grid.case.json `run`
// writes beside a grid). Outputs and refinement are left out: they describe a run, not the
// grid.
std::string case_to_json(const Case& c);

}  // namespace hexmesh

// Case files: the JSON a user writes to describe a run, parsed and validated into plain structs.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

// Bad user input: the message names the file, key or line and what was expected.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A body as written in the case: a primitive, or a CSG node over children, with an
// optional transform (applied as scale, then rotate, then translate).
struct GeometrySpec {
    std::string kind;  // sphere ellipsoid box cylinder torus cone file | union intersection difference
    Vec3 center = Vec3::Zero();
    double radius = 0;        // sphere, cylinder
    Vec3 semi_axes = Vec3::Zero();  // ellipsoid
    Vec3 size = Vec3::Zero();       // box: full edge lengths
    double height = 0;              // cylinder, cone: full height along z
    double major_radius = 0, minor_radius = 0;  // torus in the xy plane
    double bottom_radius = 0, top_radius = 0;   // cone (frustum), bottom at lower z
    std::vector<GeometrySpec> children;         // CSG operands, in order
    std::string file;        // file: surface (STL OBJ OFF PLY), resolved against the case's folder
    double voxel_size = 0;   // file: voxel of its signed distance field (0: longest side / 256)
    Vec3 translate = Vec3::Zero();
    Vec3 rotate_axis = Vec3::UnitZ();
    double rotate_degrees = 0;
    double scale = 1;
};

struct GridSpec {
    std::string topology = "o-h";  // "o-h" | "single-block"
    int cells_per_edge = 20;        // o-h: cells along each core/patch edge
    int wall_cells = 10;            // o-h: cells from the core to the wall
    double core_size = 0.45;        // o-h: core half-size / body half extents
    std::array<int, 3> cells = {20, 20, 20};  // single-block
    std::optional<Vec3> center;
};

struct BoundaryLayerSpec {
    double first_height = 0;  // geometry units
    double growth_ratio = 1;
    int layers = 0;
};

struct SolverSpec {
    std::string method = "newton-cg";
    double theta = 0.8;
    int max_iterations = 200;
};

struct Case {
    std::string path;  // the file it came from, for messages
    GeometrySpec geometry;
    GridSpec grid;
    std::optional<BoundaryLayerSpec> boundary_layer;
    SolverSpec solver;
    std::vector<std::string> outputs = {"vtk"};
};

// Reads and validates a case file. Unknown keys, wrong types and out-of-range values throw
// InputError naming the key path (e.g. "grid.cells_per_edge") and the expected value.
Case read_case(const std::string& path);

// Same, from JSON text; `path` only labels messages.
Case parse_case(const std::string& text, const std::string& path);

}  // namespace hexmesh

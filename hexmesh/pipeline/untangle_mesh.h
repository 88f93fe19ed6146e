// The `untangle` job: a hex or tet mesh from a file, its boundary fixed or slipping, made valid.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/pipeline/boundary_geometry.h"
#include "hexmesh/quality/mesh_quality.h"
#include "untangle/untangle.h"

namespace hexmesh {

enum class BoundaryMode { fixed, slip };

struct UntangleMeshOptions {
    untangle::UntangleOptions untangle;
    BoundaryMode boundary = BoundaryMode::fixed;
    // slip: the surface boundary vertices slide on; absent: the mesh's own boundary faces,
    // triangulated. Its creases (dihedral angle > feature_angle) become feature edges.
    std::optional<TriangleSurface> surface;
    // slip: an implicit body (or any other geometry) instead of `surface`.
    std::optional<BoundaryGeometry> geometry;
    double feature_angle_degrees = 30;
    // Target cell size: each cell's own mean edge length (keeps the grading of a graded
    // mesh), or the mean over the whole mesh (robust when the input is badly distorted).
    bool uniform_target = false;
    // Set: tets get regular targets from this sizing function (sized_tet_targets of
    // tet_mesh_case.h) instead of their own or the mean size.
    std::function<double(const Vec3&)> tet_size;
};

// A corner tet that is inverted while its four vertices may not move: no method that keeps
// them fixed can repair it.
struct BlockedElement {
    Id cell = 0;     // hex (or tet) index in the input
    int corner = 0;  // hex corner 0..7 (0 for a tet)
    Vec3 position;   // the corner vertex
};

struct UntangleMeshResult {
    untangle::UntangleResult solve;
    std::optional<QualityReport> hex_before, hex_after;  // for hex meshes
    std::vector<BlockedElement> blocked;                 // found before solving
    Id slip_vertices = 0, feature_vertices = 0, fixed_vertices = 0;
    double max_surface_distance = 0;  // of slip/feature vertices to the surface, after
};

// Untangles and optimizes `mesh` in place (hexes split into their 8 corner tets with
// box-corner targets sized to each hex; tets with regular targets sized to each tet).
// Vertex kinds: a "fixed" flag from the file wins; otherwise boundary vertices are fixed
// (BoundaryMode::fixed) or slip / feature edge / corner (BoundaryMode::slip); the rest is
// interior. With a fixed boundary, inverted elements whose vertices are all fixed are
// listed in `blocked` (the solve still runs and does what it can).
UntangleMeshResult untangle_volume_mesh(VolumeMesh& mesh, const UntangleMeshOptions& options);

// One line per blocked element ("cell 12 corner 3 at (x, y, z): ...") for the user.
std::string describe_blocked(const std::vector<BlockedElement>& blocked);

// What options.geometry or options.surface the boundary slips on, from the file at `path`: a
// case file (.json: its body, or its surface file, and its tet sizing for the targets of tets)
// or a surface file (.stl .obj .off .ply).
void slip_on_file(const std::string& path, UntangleMeshOptions& options);

// Writes `mesh` (after untangle_volume_mesh, `r` its result) to `path` and, unless
// `settings_json` is null, its report page beside it (titled `title`, with those settings);
// returns the paths written.
std::vector<std::string> write_untangled_mesh(const VolumeMesh& mesh, const UntangleMeshResult& r,
                                              const std::string& path, const std::string& title,
                                              const std::string* settings_json);

}  // namespace hexmesh

// Tetrahedral meshes of implicit bodies: CGAL's Delaunay refinement (Mesh_3) to a sizing
// function, with the body's creases protected, and CGAL's own sliver removal (perturb, then
// exude) on the same mesh for comparison with the variational optimizer.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

struct TetMeshOptions {
    // Target edge length at a point (> 0, geometry units): the sizing function.
    std::function<double(const Vec3&)> size;
    double facet_distance = 0;     // > 0: surface facets' circumcentres at most this far from u = 0
    double facet_angle = 25;       // degrees: lower bound of the surface triangles' angles
    double radius_edge_ratio = 3;  // upper bound of circumradius / shortest edge of a tet
    // Crease polylines of the body to protect (surface/crease_curves.h): vertices are laid
    // along them first, so the mesh keeps the sharp edges. Open polylines meet at equal end
    // points (the corners); a closed one repeats its first point.
    std::vector<std::vector<Vec3>> features;
    // Corners of the body to protect as well: those that end no polyline (a cone's apex) need
    // it; polyline ends may be listed too.
    std::vector<Vec3> corners;
    bool cgal_sliver_removal = false;  // also run CGAL's perturb + exude on a copy
    // The smallest dihedral angle (degrees) CGAL's perturber aims at; 0 is CGAL's default,
    // 12 degrees (what make_mesh_3 does). It stops once every tet reaches it or no move helps.
    double cgal_sliver_bound = 0;
    double cgal_time_limit = 0;  // seconds for perturb and for exude each; 0: no limit
};

// A tet mesh with, per point, where it lies: 0 a corner, 1 a crease, 2 the surface u = 0,
// 3 the interior (CGAL's in_dimension).
struct PlacedTetMesh {
    TetMesh mesh;  // tets positively oriented
    std::vector<std::int8_t> dimension;
};

struct TetMeshGeneration {
    PlacedTetMesh refined;  // Delaunay refinement only
    double seconds = 0;
    std::optional<PlacedTetMesh> cgal_optimized;  // refined, then perturbed and exuded by CGAL
    double cgal_seconds = 0;                      // of perturb + exude
};

// Meshes the set u < 0 of `body`. Deterministic for given inputs. Throws
// std::invalid_argument when the sizing function is missing or not positive at the body's
// centre, std::runtime_error when refinement yields no tet (the body is thinner than the
// sizes asked for).
TetMeshGeneration generate_tet_mesh(const ImplicitFunction& body, const TetMeshOptions& options);

// Removes the boundary caps: tets whose four points lie on the boundary (dimension < 3) with
// at least two faces on the boundary and a dihedral angle below max_degrees at an edge that
// is not along a crease (both ends of dimension <= 1: there the angle is the body's own).
// Such a tet spans a curved part of the surface and stays flat whatever its points do on it;
// without it, its two inner faces become boundary faces (off u = 0 by about the facets'
// own chord error). One pass; points no tet uses any more are dropped. Returns the count.
Id remove_boundary_caps(PlacedTetMesh& placed, double max_degrees);

}  // namespace hexmesh

// Health report of a triangle surface: counts a user needs before trusting its SDF.
#pragma once

#include <optional>
#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

struct SurfaceDiagnostics {
    long long points = 0, triangles = 0;
    Box3 bounds;
    long long edges = 0;                 // distinct undirected edges
    long long boundary_edges = 0;        // used by one triangle (the surface is open there)
    long long non_manifold_edges = 0;    // used by three or more triangles
    long long inconsistent_edges = 0;    // two triangles run the edge the same way (flipped)
    long long degenerate_triangles = 0;  // zero area: repeated or collinear points
    long long self_intersections = 0;    // pairs of non-degenerate triangles that cross
    std::vector<int> degenerate_ids;     // the first few degenerate triangles (ids)

    bool watertight() const {
        return boundary_edges == 0 && non_manifold_edges == 0 && inconsistent_edges == 0 &&
               self_intersections == 0 && degenerate_triangles == 0;
    }
};

// Self-intersections come from CGAL Polygon Mesh Processing on the non-degenerate
// triangles (non-manifold points split first); two triangles that share a point of the
// input only touching there are not counted.
SurfaceDiagnostics diagnose_surface(const TriangleSurface& surface);

// Zero area: repeated ids or |(b - a) x (c - a)| <= 1e-12 * (longest edge)^2, the rule the
// readers apply.
bool is_degenerate_triangle(const TriangleSurface& surface, int triangle);

// The surface without its zero-area triangles (is_degenerate_triangle), when removing them
// keeps it a surface: a triangle with a repeated point is dropped, a needle or cap (three
// points on a line) goes by flipping its longest edge or collapsing its shortest (CGAL Polygon
// Mesh Processing, remove_degenerate_faces), as marching cubes and some CAD exports leave them.
// `removed`: how many zero-area triangles it had. nullopt when the triangles do not make an
// oriented manifold surface, none is left or some zero-area triangle stays; the surface itself when
// it has none.
std::optional<TriangleSurface> without_zero_area_triangles(const TriangleSurface& surface,
                                                           long long& removed);

}  // namespace hexmesh

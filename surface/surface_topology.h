// Topology of a triangle surface: its connected pieces, their holes and handles.
#pragma once

#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

// One connected piece of a surface (triangles joined through shared points; points with
// identical coordinates count as one).
struct SurfaceComponent {
    long long points = 0, edges = 0, triangles = 0;
    long long boundary_edges = 0;  // used by one triangle: the piece is open there
    long long boundary_loops = 0;  // holes: closed chains of boundary edges
    long long euler = 0;           // V - E + F
    // Handles of the piece with its holes capped: (2 - euler - boundary_loops) / 2, so a
    // sphere has 0, a torus (or a ring, a knot's tube, a mug) 1.
    long long genus = 0;
    Box3 bounds;
    // The widest hole: the diagonal of the bounds of its boundary points (a set of boundary
    // edges joined at their points; loops through a common point are one here), and their
    // centre; the first such set in point order among equally wide ones. 0 and the origin when
    // the piece is closed.
    double widest_hole = 0;
    Vec3 widest_hole_at = Vec3::Zero();
};

struct SurfaceTopology {
    std::vector<SurfaceComponent> components;  // largest (most triangles) first
    long long non_manifold_edges = 0;          // used by three or more triangles
};

// For each point, the first point with the same coordinates (itself when none comes before).
std::vector<int> welded_ids(const std::vector<Vec3>& points);

// Components by union-find over the triangles' points; for each, V - E + F and the boundary
// loops (a boundary point with more than two boundary edges closes several loops, each
// counted). Zero-area triangles count like any other.
SurfaceTopology surface_topology(const TriangleSurface& surface);

}  // namespace hexmesh

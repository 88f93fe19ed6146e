// Quality metrics of tetrahedral meshes: dihedral angles, radius ratio, slivers, validity.
#pragma once

#include <array>

#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// The 6 dihedral angles (degrees, in [0, 180]) of the tet p0..p3, at its edges 01 02 03 12 13 23:
// the angle between the two faces meeting at the edge. A regular tet has 70.53 everywhere.
// A degenerate edge or face gives 0.
// The four points of tet `cell` of `mesh`, in its node order.
std::array<Vec3, 4> tet_corners(const TetMesh& mesh, Id cell);

std::array<double, 6> dihedral_angles(const std::array<Vec3, 4>& p);

// The smallest of dihedral_angles(p), from the faces' normals with one arc cosine: the cheap
// form for searches that evaluate it many times. 0 for a flat tet or one with a degenerate
// face; an inverted tet has its mirror image's angles.
double smallest_dihedral_angle(const std::array<Vec3, 4>& p);

// det[p1 - p0, p2 - p0, p3 - p0] / 6: the volume, negative for an inverted tet.
double signed_volume(const std::array<Vec3, 4>& p);

// Sum of the signed volumes of all tets of `mesh`.
double signed_volume(const TetMesh& mesh);

// 3 r / R (inradius over circumradius, normalized: 1 for a regular tet, 0 when flat);
// 0 for a tet with det[p1 - p0, p2 - p0, p3 - p0] <= 0.
double radius_ratio(const std::array<Vec3, 4>& p);

struct TetQualityReport {
    Id cells = 0, points = 0;
    Id inverted = 0;  // exact det[p1 - p0, p2 - p0, p3 - p0] <= 0 (CGAL's orientation predicate)
    Id slivers = 0;   // some dihedral angle below sliver_degrees
    double sliver_degrees = 10;
    double min_dihedral = 0, max_dihedral = 0;  // degrees, over all tets
    double mean_min_dihedral = 0;               // mean over tets of their smallest dihedral angle
    double min_radius_ratio = 0, mean_radius_ratio = 0;
};

// Every metric above over all tets of `mesh` (parallel, deterministic).
TetQualityReport measure_tet_quality(const TetMesh& mesh, double sliver_degrees = 10);

}  // namespace hexmesh

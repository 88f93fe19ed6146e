// The rings of the axial core around its axis: evenly spaced, or fitted to the body's creases
// so circles around the axis run along grid lines.
#pragma once

#include <vector>

#include "volume/axial_creases.h"

namespace hexmesh {

// Rings around `axis` in the two cube faces across it, as the axial core lays them out. In the
// plane of those faces (the other two cube coordinates, b and c): a central square
// |b|, |c| <= column = radius[0], then rings s = 1 .. cells, ring s at distance radius[s] from the
// axis along b and c. roundness[s] blends ring s from the square |b|, |c| = radius[s] (0) to the
// circle of that radius (1); the first ring is the column's square, the last the frame's
// inner square (roundness 0 at both; axial_frame_edge).
struct AxialRings {
    int axis = 2;
    std::vector<double> radius;     // cells + 1 values, radius[0] the column's half-width
    std::vector<double> roundness;  // cells + 1 values in [0, 1]
    int cells() const { return int(radius.size()) - 1; }
    double column() const { return radius.front(); }  // the column's half-width
};

// Rings with `cells` cells, evenly spaced from a column of half-width outer / 2 to `outer`,
// round in the middle (roundness sin(pi s / cells)) as far as they stay nested: each ring
// reaches further along the diagonals than the one inside it by at least a quarter of its step
// along the axes (a circle reaches less far than a square; fitted rings are held to the same).
AxialRings even_axial_rings(int axis, int cells, double outer);

// Rings fitted to the creases around the axis: each crease inside `outer` gets a ring through
// it along the edge-midpoint half-lines, as round as the crease (circle: reach = radius;
// square: reach = sqrt(2) radius); in between, the rings' reach along the diagonals grows
// evenly with their radius, from the column's square to the frame's. The column is half the
// first crease's radius (at most outer / 2); the other rings are spread evenly in arc length
// along the wall between the creases. At most cells - 1 creases are fitted, nearest the axis
// first; without creases, even_axial_rings.
AxialRings fit_axial_rings(const AxialCreases& creases, int axis, int cells, double outer);

}  // namespace hexmesh

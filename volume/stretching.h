// One-dimensional node distributions along grid lines: wall layers with a growth ratio.
#pragma once

#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

// Boundary-layer law along a wall-normal line: `layers` cells of thickness
// first_height * growth_ratio^m (m = 0 at the wall), in geometry units.
struct WallLayers {
    double first_height = 0;
    double growth_ratio = 1;
    int layers = 0;
};

// How many of the law's layers a line of the given length and cell count takes: all of them
// when they fit (thinner than the line, with a cell left beyond them); else, where the body is
// thin, the most whose thickness is at most half the line and that leave a cell beyond them,
// each at the law's height (the layer is cut, its first height kept); 0 when not even the first
// layer fits so.
int layers_that_fit(double length, int cells, const WallLayers& law);

// Throws std::invalid_argument, naming `wall` when given, unless the whole law fits the line
// (layers_that_fit(length, cells, law) == law.layers): for constructions that lay the same
// layers on every line.
void require_whole_layers(double length, int cells, const WallLayers& law,
                          const Vec3* wall = nullptr);

// Distances from the wall of the cells+1 nodes of a line of the given length:
// d[0] = 0, d[cells] = length, increasing. The first layers_that_fit(length, cells, law) cells
// follow the law exactly; the remaining cells continue geometrically from the last layer
// thickness with the ratio that fills the line. Throws std::invalid_argument when not even the
// first layer fits, naming `wall` (the line's wall end) when given.
std::vector<double> wall_distances(double length, int cells, const WallLayers& law,
                                   const Vec3* wall = nullptr);

// Uniform distances 0, length/cells, ..., length.
std::vector<double> uniform_distances(double length, int cells);

// Total thickness of the law's layers.
double layers_thickness(const WallLayers& law);

// The law's heights above the wall of its layer nodes: d[0] = 0, d[m] = d[m - 1] +
// first_height growth_ratio^(m - 1) up to d[law.layers] (as extrude_wall_layers lays them).
std::vector<double> layer_heights(const WallLayers& law);

// Ratio q > 0 such that first * (q + q^2 + ... + q^cells) = total, by bisection.
double geometric_ratio(double first, int cells, double total);

}  // namespace hexmesh

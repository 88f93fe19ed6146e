#include "volume/stretching.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hexmesh {

double layers_thickness(const WallLayers& law) {
    double t = 0, h = law.first_height;
    for (int m = 0; m < law.layers; ++m, h *= law.growth_ratio) t += h;
    return t;
}

std::vector<double> layer_heights(const WallLayers& law) {
    std::vector<double> d(size_t(std::max(law.layers, 0)) + 1, 0.0);
    for (int m = 1; m <= law.layers; ++m)
        d[m] = d[m - 1] + law.first_height * std::pow(law.growth_ratio, m - 1);
    return d;
}

double geometric_ratio(double first, int cells, double total) {
    auto sum = [&](double q) {
        double s = 0, p = 1;
        for (int j = 0; j < cells; ++j) s += (p *= q);
        return first * s;
    };
    double lo = 1e-6, hi = 1;
    while (sum(hi) < total) hi *= 2;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        (sum(mid) < total ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

std::vector<double> uniform_distances(double length, int cells) {
    std::vector<double> d(cells + 1);
    for (int m = 0; m <= cells; ++m) d[m] = length * m / cells;
    return d;
}

namespace {

// "boundary layer of N layers (T thick) does not fit the wall-normal line of C cells and length
// L[ from the wall at (x, y, z)]": the head of both refusals.
std::string misfit(const WallLayers& law, int cells, double length, const Vec3* wall) {
    return fmt::format(
        "boundary layer of {} layers ({:.4g} thick) does not fit the wall-normal line of {} "
        "cells and length {:.4g}{}",
        law.layers, layers_thickness(law), cells, length,
        wall ? fmt::format(" from the wall at ({:.4g}, {:.4g}, {:.4g})", wall->x(), wall->y(),
                           wall->z())
             : std::string());
}

}  // namespace

void require_whole_layers(double length, int cells, const WallLayers& law, const Vec3* wall) {
    if (law.layers <= 0 || layers_that_fit(length, cells, law) == law.layers) return;
    throw std::invalid_argument(misfit(law, cells, length, wall) +
                                ": use fewer layers, a smaller first height or growth ratio");
}

int layers_that_fit(double length, int cells, const WallLayers& law) {
    if (law.layers <= 0) return 0;
    if (layers_thickness(law) < length && cells - law.layers >= 1) return law.layers;
    int m = 0;
    while (m + 1 < std::min(law.layers, cells) &&
           layers_thickness({law.first_height, law.growth_ratio, m + 1}) <= 0.5 * length)
        ++m;
    return m;
}

std::vector<double> wall_distances(double length, int cells, const WallLayers& whole_law,
                                   const Vec3* wall) {
    if (whole_law.layers == 0) return uniform_distances(length, cells);
    const WallLayers law{whole_law.first_height, whole_law.growth_ratio,
                         layers_that_fit(length, cells, whole_law)};
    if (law.layers == 0) {
        throw std::invalid_argument(
            misfit(whole_law, cells, length, wall) +
            fmt::format(", not even its first layer ({:.4g}) in half of it: use a smaller first "
                        "height",
                        law.first_height));
    }
    const double thickness = layers_thickness(law);
    const int rest = cells - law.layers;
    std::vector<double> d(cells + 1, 0.0);
    double h = law.first_height;
    for (int m = 0; m < law.layers; ++m, h *= law.growth_ratio) d[m + 1] = d[m] + h;
    const double last = law.first_height * std::pow(law.growth_ratio, law.layers - 1);
    const double q = geometric_ratio(last, rest, length - thickness);
    h = last;
    for (int m = law.layers; m < cells; ++m) d[m + 1] = d[m] + (h *= q);
    d[cells] = length;
    return d;
}

}  // namespace hexmesh

#include "volume/stretching.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace hexmesh {

double layers_thickness(const WallLayers& law) {
    double t = 0, h = law.first_height;
    for (int m = 0; m < law.layers; ++m, h *= law.growth_ratio) t += h;
    return t;
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

std::vector<double> wall_distances(double length, int cells, const WallLayers& law,
                                   const Vec3* wall) {
    if (law.layers == 0) return uniform_distances(length, cells);
    const double thickness = layers_thickness(law);
    const int rest = cells - law.layers;
    if (rest < 1 || thickness >= length) {
        throw std::invalid_argument(fmt::format(
            "boundary layer of {} layers ({:.4g} thick) does not fit the wall-normal line of "
            "{} cells and length {:.4g}{}: use fewer layers, a smaller first height or growth "
            "ratio, or more wall cells",
            law.layers, thickness, cells, length,
            wall ? fmt::format(" from the wall at ({:.4g}, {:.4g}, {:.4g})", wall->x(), wall->y(),
                               wall->z())
                 : std::string()));
    }
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

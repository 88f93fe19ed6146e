// The rings of the axial core: evenly spaced, or fitted to the creases around its axis and
// spread evenly in arc length along the wall between them.
#include "volume/axial_rings.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;

// Arc length along a polyline of wall points, at each point.
std::vector<double> arc_lengths(const std::vector<Vec3>& p) {
    std::vector<double> s(p.size(), 0.0);
    for (size_t i = 1; i < p.size(); ++i) s[i] = s[i - 1] + (p[i] - p[i - 1]).norm();
    return s;
}

// Linear interpolation of ys at x in the increasing table xs (clamped at its ends).
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    if (x <= xs.front()) return ys.front();
    if (x >= xs.back()) return ys.back();
    const size_t i = std::upper_bound(xs.begin(), xs.end(), x) - xs.begin();
    const double f = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return ys[i - 1] + f * (ys[i] - ys[i - 1]);
}

// Cells per segment of the given lengths: at least one each, `cells` in all, the rest
// shared in proportion to length (largest remainder).
std::vector<int> share_cells(const std::vector<double>& lengths, int cells) {
    const int m = int(lengths.size());
    double total = 0;
    for (double x : lengths) total += std::max(x, 0.0);
    std::vector<int> count(m, 1);
    std::vector<double> want(m);
    for (int i = 0; i < m; ++i)  // no length at all: shared evenly
        want[i] = (cells - m) * (total > 0 ? std::max(lengths[i], 0.0) / total : 1.0 / m);
    for (int i = 0; i < m; ++i) count[i] += int(std::floor(want[i]));
    int left = cells - std::accumulate(count.begin(), count.end(), 0);
    std::vector<int> order(m);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return want[a] - std::floor(want[a]) > want[b] - std::floor(want[b]);
    });
    for (int i = 0; left > 0; i = (i + 1) % m, --left) ++count[order[i]];
    return count;
}

// Lowers each ring's roundness as far as needed for the rings to stay nested: a round ring
// reaches less far along the diagonals than a square one, so each ring's diagonal reach must
// exceed the previous ring's by at least a quarter of its step along the axes.
void keep_rings_nested(AxialRings& rings) {
    const double root2 = std::sqrt(2.0);
    double previous =
        root2 * rings.radius[0] * (1 - rings.roundness[0]) + rings.radius[0] * rings.roundness[0];
    for (int s = 1; s <= rings.cells(); ++s) {
        const double w = rings.radius[s];
        const double least = previous + 0.25 * (w - rings.radius[s - 1]);
        const double most_round = (root2 - least / w) / (root2 - 1);
        rings.roundness[s] = std::clamp(std::min(rings.roundness[s], most_round), 0.0, 1.0);
        previous = w * (root2 - rings.roundness[s] * (root2 - 1));
    }
}

}  // namespace

AxialRings even_axial_rings(int axis, int cells, double outer) {
    AxialRings rings;
    rings.axis = axis;
    const double column = outer / 2;
    for (int s = 0; s <= cells; ++s) {
        rings.radius.push_back(s == cells ? outer : column + (outer - column) * s / cells);
        rings.roundness.push_back(s == 0 || s == cells ? 0.0 : std::sin(pi * s / cells));
    }
    keep_rings_nested(rings);
    return rings;
}

AxialRings fit_axial_rings(const AxialCreases& creases, int axis, int cells, double outer) {
    // Creases strictly inside (0, outer) and increasing, as find_axial_creases gives them.
    std::vector<double> rings_at, reach_at;
    for (size_t k = 0; k < creases.radius.size(); ++k) {
        const double x = creases.radius[k];
        if (x > 1e-3 * outer && x < outer * (1 - 1e-3) && (rings_at.empty() || x > rings_at.back()))
            rings_at.push_back(x), reach_at.push_back(creases.reach[k]);
    }
    if (creases.meridian.size() < 2 || creases.meridian.size() != creases.w.size())
        rings_at.clear();
    if (int(rings_at.size()) > cells - 1) {
        rings_at.resize(std::max(cells - 1, 0));
        reach_at.resize(rings_at.size());
    }
    if (rings_at.empty()) return even_axial_rings(axis, cells, outer);

    AxialRings rings;
    rings.axis = axis;
    const double column = std::min(outer / 2, rings_at.front() / 2);
    const std::vector<double>& w = creases.w;
    const std::vector<double> length = arc_lengths(creases.meridian);
    std::vector<double> stops = {column};
    stops.insert(stops.end(), rings_at.begin(), rings_at.end());
    stops.push_back(outer);
    std::vector<double> segment;
    for (size_t i = 0; i + 1 < stops.size(); ++i)
        segment.push_back(interpolate(w, length, stops[i + 1]) - interpolate(w, length, stops[i]));
    const std::vector<int> count = share_cells(segment, cells);
    rings.radius.push_back(column);
    for (size_t i = 0; i < count.size(); ++i) {
        const double from = interpolate(w, length, stops[i]);
        for (int s = 1; s <= count[i]; ++s) {
            const double at = from + segment[i] * s / count[i];
            rings.radius.push_back(s == count[i] ? stops[i + 1] : interpolate(length, w, at));
        }
    }
    // Each ring's reach along the diagonals: the creases' own, and in between it grows evenly
    // with the radius, from the column's square to the frame's.
    const double root2 = std::sqrt(2.0);
    std::vector<double> reach = {root2 * column};
    reach.insert(reach.end(), reach_at.begin(), reach_at.end());
    reach.push_back(root2 * outer);
    for (int s = 0; s <= cells; ++s) {
        const double x = rings.radius[s];
        const double d = interpolate(stops, reach, x);
        rings.roundness.push_back(std::clamp((root2 - d / x) / (root2 - 1), 0.0, 1.0));
    }
    keep_rings_nested(rings);
    return rings;
}

}  // namespace hexmesh

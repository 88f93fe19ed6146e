// place_nodes_on_paths: the nodes of lines along a continuation's paths, by arc length in the
// boundary layer, by level up to the far surface, geometric beyond.
#include "volume/path_lines.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace hexmesh {
namespace {

// A polyline with its arc length and a level rising along it.
struct LevelledLine {
    std::vector<Vec3> x;
    std::vector<double> arc, level;

    Vec3 at_arc(double a) const {
        const auto [k, w] = segment_at(a);
        return x[k - 1] + w * (x[k] - x[k - 1]);
    }
    double level_at_arc(double a) const {
        const auto [k, w] = segment_at(a);
        return level[k - 1] + w * (level[k] - level[k - 1]);
    }
    // The segment [k - 1, k] holding arc length a and the weight of x[k] there (a line has at
    // least two points: exterior_paths refuses shorter ones).
    std::pair<size_t, double> segment_at(double a) const {
        size_t k = std::upper_bound(arc.begin(), arc.end(), a) - arc.begin();
        k = std::clamp<size_t>(k, 1, x.size() - 1);
        return {k, std::clamp((a - arc[k - 1]) / std::max(arc[k] - arc[k - 1], 1e-300), 0.0, 1.0)};
    }
    // The first point at `c` (the level taken as non-decreasing: its running maximum).
    Vec3 at_level(double c) const {
        double running = level[0];
        for (size_t k = 1; k < x.size(); ++k) {
            const double next = std::max(running, level[k]);
            if (next >= c) {
                const double w = next > running ? (c - running) / (next - running) : 1.0;
                return x[k - 1] + std::clamp(w, 0.0, 1.0) * (x[k] - x[k - 1]);
            }
            running = next;
        }
        return x.back();
    }
};

}  // namespace

void place_nodes_on_paths(const WallPaths& paths, const std::vector<Vec3>& wall,
                          const std::vector<Vec3>& far, int nk, const WallLayers& law,
                          const std::function<void(Id s, const std::vector<Vec3>& x)>& set_line) {
    const Id ns = Id(wall.size());
    const int m = std::min(law.layers, nk - 2);  // boundary-layer cells along the path
    const double growth = law.layers > 0 ? std::max(law.growth_ratio, 1.05) : 1.2;
    std::vector<LevelledLine> lines(ns);
    std::vector<double> top(ns);  // each line's level at the top of the boundary layer
    tbb::parallel_for(Id(0), ns, [&](Id s) {
        LevelledLine& l = lines[s];
        l.x = paths.lines[s];
        l.x.front() = wall[s];
        l.level = paths.levels[s];
        l.arc.assign(l.x.size(), 0);
        for (size_t k = 1; k < l.x.size(); ++k)
            l.arc[k] = l.arc[k - 1] + (l.x[k] - l.x[k - 1]).norm();
        top[s] = std::max(
            l.level_at_arc(m > 0 ? layers_thickness({law.first_height, law.growth_ratio, m}) : 0.0),
            1e-12 * paths.far_level);
    });
    // Cells between the boundary layer and the far surface, and from there to the far field:
    // as many growth-ratio steps as each part spans on a typical line.
    std::vector<double> sorted = top;
    std::nth_element(sorted.begin(), sorted.begin() + ns / 2, sorted.end());
    const double typical_top = sorted[ns / 2];
    double outer = 0, beyond = 0;
    for (Id s = 0; s < ns; ++s)
        outer += (lines[s].x.back() - paths.centre).norm() / double(ns),
            beyond += (far[s] - lines[s].x.back()).norm() / double(ns);
    const double level_steps = std::log(paths.far_level / typical_top) / std::log(growth);
    const double far_steps =
        std::log1p(beyond / std::max(outer, 1e-300) * (growth - 1)) / std::log(growth) + 1;
    const int free_cells = nk - m;
    const int level_cells = std::clamp(
        int(std::lround(free_cells * level_steps / (level_steps + far_steps))), 1, free_cells - 1);
    const int k_far = m + level_cells;  // the node on the far surface

    tbb::parallel_for(Id(0), ns, [&](Id s) {
        const LevelledLine& l = lines[s];
        std::vector<Vec3> x(nk + 1);
        x[0] = wall[s];
        double a = 0;
        for (int k = 1; k <= m; ++k) {
            a += law.first_height * std::pow(law.growth_ratio, k - 1);
            x[k] = l.at_arc(a);
        }
        const double lo = std::log(top[s]), hi = std::log(paths.far_level);
        for (int k = m + 1; k < k_far; ++k)
            x[k] = l.at_level(std::exp(lo + (hi - lo) * double(k - m) / double(k_far - m)));
        x[k_far] = l.x.back();
        // Beyond: geometric from the last cell's height to the far-field node.
        const double rest = (far[s] - x[k_far]).norm();
        const double first = std::max((x[k_far] - x[k_far - 1]).norm(), 1e-9 * rest);
        const int cells = nk - k_far;
        // Cells first q, first q^2, ... adding up to the rest (uniform if even `first` is too
        // long for them).
        const bool uniform = first * cells >= rest;
        const double q = uniform ? 1.0 : geometric_ratio(first, cells, rest);
        double d = 0, step = uniform ? rest / cells : first * q;
        for (int k = k_far + 1; k < nk; ++k) {
            d += step, step *= q;
            x[k] = x[k_far] + std::min(d / rest, 1.0) * (far[s] - x[k_far]);
        }
        x[nk] = far[s];
        set_line(s, x);
    });
}

}  // namespace hexmesh

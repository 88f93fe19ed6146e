#include "surface/level_sets.h"

#include <tbb/blocked_range3d.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <tuple>

namespace hexmesh {

std::optional<Vec3> deepest_point(const ImplicitFunction& body, double step,
                                  const std::function<double(const Vec3&)>& depth) {
    const Box3 box = body.bounds();
    const Eigen::Vector3i n = ((box.size() / step).array().ceil().cast<int>() + 1).max(2);
    // Depth of x, or -infinity outside.
    const auto depth_at = [&](const Vec3& x) {
        const double u = body.value(x);
        if (!(u < 0)) return -std::numeric_limits<double>::infinity();
        return depth ? depth(x) : -u;
    };
    struct Best {
        double depth = -std::numeric_limits<double>::infinity();
        Vec3 x = Vec3::Zero();
    };
    const auto deeper = [](const Best& a, const Best& b) {
        return a.depth > b.depth || (a.depth == b.depth && std::tie(a.x.x(), a.x.y(), a.x.z()) <
                                                               std::tie(b.x.x(), b.x.y(), b.x.z()));
    };
    const Best best = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, n.z()), Best{},
        [&](const tbb::blocked_range<int>& r, Best b) {
            for (int k = r.begin(); k != r.end(); ++k)
                for (int j = 0; j < n.y(); ++j)
                    for (int i = 0; i < n.x(); ++i) {
                        const Vec3 x = box.lo + step * Vec3(i, j, k);
                        const Best here{depth_at(x), x};
                        if (deeper(here, b)) b = here;
                    }
            return b;
        },
        [&](const Best& a, const Best& b) { return deeper(a, b) ? a : b; });
    if (!(best.depth > -std::numeric_limits<double>::infinity())) return std::nullopt;
    // Pattern search: the 26 neighbours at the step, halved until a fiftieth of it.
    Best at = best;
    for (double s = 0.5 * step; s > 0.02 * step; s *= 0.5) {
        bool moved = true;
        while (moved) {
            moved = false;
            for (int c = 0; c < 27; ++c) {
                if (c == 13) continue;
                const Vec3 x = at.x + s * Vec3(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
                const Best here{depth_at(x), x};
                if (here.depth > at.depth) at = here, moved = true;
            }
        }
    }
    return at.x;
}

std::vector<Vec3> deepest_candidates(const ImplicitFunction& body, double step, int count,
                                     const std::function<double(const Vec3&)>& depth) {
    const Box3 box = body.bounds();
    const Eigen::Vector3i n = ((box.size() / step).array().ceil().cast<int>() + 1).max(2);
    const auto at = [&](const Eigen::Vector3i& c) {
        return Vec3(box.lo + step * c.cast<double>());
    };
    const auto index = [&](const Eigen::Vector3i& c) {
        return (size_t(c.z()) * n.y() + c.y()) * n.x() + c.x();
    };
    constexpr double outside = -std::numeric_limits<double>::infinity();
    std::vector<double> depths(size_t(n.x()) * n.y() * n.z());
    tbb::parallel_for(0, n.z(), [&](int k) {
        for (int j = 0; j < n.y(); ++j)
            for (int i = 0; i < n.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                const double u = body.value(at(c));
                depths[index(c)] = !(u < 0) ? outside : depth ? depth(at(c)) : -u;
            }
    });
    const double deepest = *std::max_element(depths.begin(), depths.end());
    if (deepest == outside) return {};
    // The plateau's points, each with the share of its ball of radius 2 deepest inside.
    struct Candidate {
        double share;
        Eigen::Vector3i c;
    };
    std::vector<Candidate> plateau;
    const int reach = int(std::ceil(2 * deepest / step));
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j)
            for (int i = 0; i < n.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                if (!(depths[index(c)] >= deepest - 0.5 * step)) continue;
                long long in = 0, all = 0;
                for (int dk = -reach; dk <= reach; ++dk)
                    for (int dj = -reach; dj <= reach; ++dj)
                        for (int di = -reach; di <= reach; ++di) {
                            if ((di * di + dj * dj + dk * dk) * step * step > 4 * deepest * deepest)
                                continue;
                            const Eigen::Vector3i q = c + Eigen::Vector3i(di, dj, dk);
                            ++all;
                            in += (q.array() >= 0).all() && (q.array() < n.array()).all() &&
                                  depths[index(q)] != outside;
                        }
                plateau.push_back({double(in) / double(all), c});
            }
    std::stable_sort(plateau.begin(), plateau.end(),
                     [](const Candidate& a, const Candidate& b) { return a.share > b.share; });
    std::vector<Vec3> chosen;
    for (const Candidate& p : plateau) {
        if (int(chosen.size()) == count) break;
        const Vec3 x = at(p.c);
        if (std::all_of(chosen.begin(), chosen.end(),
                        [&](const Vec3& y) { return (x - y).norm() >= deepest; }))
            chosen.push_back(x);
    }
    return chosen;
}

std::vector<Vec3> sphere_directions(int count) {
    std::vector<Vec3> d(count);
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1 - (2 * i + 1.0) / count, r = std::sqrt(1 - z * z);
        d[i] = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    return d;
}

bool star_shaped_level(const ImplicitFunction& f, double c, const Vec3& centre,
                       const std::vector<Vec3>& directions, double step, double reach,
                       double max_angle_deg, std::vector<Vec3>* crossings) {
    const double min_cos = std::cos(max_angle_deg * M_PI / 180);
    std::atomic<bool> star{true};
    if (crossings) crossings->assign(directions.size(), centre);
    tbb::parallel_for(size_t(0), directions.size(), [&](size_t r) {
        if (!star) return;
        const Vec3& dir = directions[r];
        int times = 0;  // the ray crosses F = c
        double previous = f.value(centre) - c;
        double t_cross = 0;
        for (double t = step; t <= reach; t += step) {
            const double u = f.value(centre + t * dir) - c;
            if ((u > 0) != (previous > 0)) {
                ++times;
                t_cross = t - step * u / (u - previous);
            }
            previous = u;
        }
        if (times != 1 || previous <= 0) {
            star = false;
            return;
        }
        const Vec3 g = f.gradient(centre + t_cross * dir);
        if (!(g.dot(dir) >= min_cos * g.norm())) star = false;
        if (crossings) (*crossings)[r] = centre + t_cross * dir;
    });
    return star;
}

}  // namespace hexmesh

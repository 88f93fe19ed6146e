#include "surface/level_sets.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <tuple>

namespace hexmesh {

namespace {

constexpr double outside = -std::numeric_limits<double>::infinity();

// Depth of x: `depth` (or -u) inside, -infinity outside.
double depth_at(const ImplicitFunction& body, const std::function<double(const Vec3&)>& depth,
                const Vec3& x) {
    const double u = body.value(x);
    if (!(u < 0)) return outside;
    return depth ? depth(x) : -u;
}

}  // namespace

DepthLattice depth_lattice(const ImplicitFunction& body, double step,
                           const std::function<double(const Vec3&)>& depth) {
    const Box3 box = body.bounds();
    DepthLattice l;
    l.lo = box.lo;
    l.step = step;
    l.n = ((box.size() / step).array().ceil().cast<int>() + 1).max(2);
    l.depths.resize(size_t(l.n.x()) * l.n.y() * l.n.z());
    tbb::parallel_for(0, l.n.z(), [&](int k) {
        for (int j = 0; j < l.n.y(); ++j)
            for (int i = 0; i < l.n.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                l.depths[l.index(c)] = depth_at(body, depth, l.at(c));
            }
    });
    return l;
}

std::optional<Vec3> deepest_point(const ImplicitFunction& body, const DepthLattice& lattice,
                                  const std::function<double(const Vec3&)>& depth) {
    struct Best {
        double depth = outside;
        Vec3 x = Vec3::Zero();
    };
    const auto deeper = [](const Best& a, const Best& b) {
        return a.depth > b.depth || (a.depth == b.depth && std::tie(a.x.x(), a.x.y(), a.x.z()) <
                                                               std::tie(b.x.x(), b.x.y(), b.x.z()));
    };
    Best best;
    for (int k = 0; k < lattice.n.z(); ++k)
        for (int j = 0; j < lattice.n.y(); ++j)
            for (int i = 0; i < lattice.n.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                const Best here{lattice.depths[lattice.index(c)], lattice.at(c)};
                if (deeper(here, best)) best = here;
            }
    if (!(best.depth > outside)) return std::nullopt;
    // Pattern search: the 26 neighbours at the step, halved until a fiftieth of it.
    Best at = best;
    for (double s = 0.5 * lattice.step; s > 0.02 * lattice.step; s *= 0.5) {
        bool moved = true;
        while (moved) {
            moved = false;
            for (int c = 0; c < 27; ++c) {
                if (c == 13) continue;
                const Vec3 x = at.x + s * Vec3(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
                const Best here{depth_at(body, depth, x), x};
                if (here.depth > at.depth) at = here, moved = true;
            }
        }
    }
    return at.x;
}

std::vector<Vec3> deepest_candidates(const DepthLattice& lattice, int count) {
    const std::vector<double>& depths = lattice.depths;
    const double deepest =
        depths.empty() ? outside : *std::max_element(depths.begin(), depths.end());
    if (deepest == outside) return {};
    // The offsets of the nodes in a ball of radius 2 deepest.
    const double step = lattice.step;
    const int reach = int(std::ceil(2 * deepest / step));
    std::vector<Eigen::Vector3i> ball;
    for (int dk = -reach; dk <= reach; ++dk)
        for (int dj = -reach; dj <= reach; ++dj)
            for (int di = -reach; di <= reach; ++di)
                if (!((di * di + dj * dj + dk * dk) * step * step > 4 * deepest * deepest))
                    ball.emplace_back(di, dj, dk);
    // The plateau's nodes, each with the share of its ball inside.
    struct Candidate {
        double share;
        Eigen::Vector3i c;
    };
    std::vector<Candidate> plateau;
    const Eigen::Vector3i& n = lattice.n;
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j)
            for (int i = 0; i < n.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                if (!(depths[lattice.index(c)] >= deepest - 0.5 * step)) continue;
                long long in = 0;
                for (const Eigen::Vector3i& d : ball) {
                    const Eigen::Vector3i q = c + d;
                    in += (q.array() >= 0).all() && (q.array() < n.array()).all() &&
                          depths[lattice.index(q)] != outside;
                }
                plateau.push_back({double(in) / double(ball.size()), c});
            }
    std::stable_sort(plateau.begin(), plateau.end(),
                     [](const Candidate& a, const Candidate& b) { return a.share > b.share; });
    std::vector<Vec3> chosen;
    for (const Candidate& p : plateau) {
        if (int(chosen.size()) == count) break;
        const Vec3 x = lattice.at(p.c);
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

// The creases around an axis of the core: rays through the cube faces across it placed on the
// wall, the sharp samples along them located exactly on their creases, clustered.
#include "volume/axial_creases.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include "surface/implicit_features.h"
#include "volume/surface_placement.h"

namespace hexmesh {
namespace {

Vec3 unit(int axis) {
    return Vec3::Unit(axis);
}

// Where the half-line t = w d + end (0 < w < 1) meets the crease near the wall point `near`
// (sampled at w = `sampled`): the crease point nearest `near` (the corner, when `corner`), and
// the w whose ray passes through it, by Gauss-Newton on the ray's direction (cube_ray is
// trilinear in t: affine in w along the faces' axes, one step; quadratic along their
// diagonals); `sampled` when that w is not within 0.01 of it.
double crease_on_half_line(const ImplicitFunction& body, const Vec3& centre,
                           const std::function<Vec3(const Vec3&)>& ray, const Vec3& d,
                           const Vec3& end, const Vec3& near, double sampled, bool corner,
                           double length_scale) {
    const Vec3 q = (corner ? snap_to_corner(body, near, length_scale)
                           : project_to_crease(body, near, length_scale)) -
                   centre;
    double w = sampled;
    for (int step = 0; step < 4; ++step) {
        constexpr double dw = 1e-4;
        const Vec3 at = ray(w * d + end);
        const Vec3 slope = (ray((w + dw) * d + end) - ray((w - dw) * d + end)) / (2 * dw);
        const Vec3 qs = q.cross(slope);  // q x (at + x slope) = 0 in the least-squares sense
        if (!(qs.squaredNorm() > 0)) return sampled;
        w -= q.cross(at).dot(qs) / qs.squaredNorm();
    }
    return std::abs(w - sampled) < 0.01 ? w : sampled;
}

}  // namespace

AxialCreases find_axial_creases(const ImplicitFunction& body, const Vec3& centre,
                                const std::function<Vec3(const Vec3&)>& ray, int axis, double outer,
                                double length_scale) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    constexpr int samples = 512;
    AxialCreases found;
    for (int i = 0; i < samples; ++i) found.w.push_back((i + 0.5) / samples);
    // The creases met along one half-line t = w dir + end, as the middles of runs of samples
    // classified sharp, each then located exactly; those next to the face's centre or its
    // frame (a tip, the patch edges) are not rings.
    auto creases_along = [&](const Vec3& dir, const Vec3& end, std::vector<Vec3>& p) {
        std::vector<double> creases;
        p.resize(samples);
        for (int i = 0; i < samples; ++i)
            p[i] = place_on_surface(body, centre, ray(found.w[i] * dir + end), length_scale);
        int run_start = -1;
        for (int i = 0; i <= samples; ++i) {
            bool sharp = false;
            if (i < samples) {
                const double spacing =
                    (p[std::min(i + 1, samples - 1)] - p[std::max(i - 1, 0)]).norm() / 2;
                sharp = classify_surface_point(body, p[i], spacing) != FeatureKind::smooth;
            }
            if (sharp && run_start < 0) run_start = i;
            if (!sharp && run_start >= 0) {
                // A short run crosses a crease; a long one runs along it (the half-line lies in
                // a plane of the crease, as a box's diagonal plane holds its vertical edge), and
                // its two ends are where the wall leaves it: corners.
                std::vector<std::pair<int, bool>> at = {{(run_start + i - 1) / 2, false}};
                if (i - run_start > 4) at = {{run_start, true}, {i - 1, true}};
                for (const auto& [sample, corner] : at) {
                    const double x = crease_on_half_line(body, centre, ray, dir, end, p[sample],
                                                         found.w[sample], corner, length_scale);
                    if (x > 0.05 && x < outer - 0.05) creases.push_back(x);
                }
                run_start = -1;
            }
        }
        return creases;
    };
    // Creases met within 0.03 of each other are one: from (w, half-line) pairs, the mean w of
    // each cluster and how many distinct half-lines met it.
    using Met = std::pair<double, int>;
    auto cluster = [](std::vector<Met> x, std::vector<double>& mean, std::vector<int>& count) {
        std::sort(x.begin(), x.end());
        for (size_t i = 0; i < x.size();) {
            size_t j = i + 1;
            while (j < x.size() && x[j].first - x[j - 1].first <= 0.03) ++j;
            double sum = 0;
            std::vector<int> lines;
            for (size_t k = i; k < j; ++k) sum += x[k].first, lines.push_back(x[k].second);
            std::sort(lines.begin(), lines.end());
            mean.push_back(sum / double(j - i));
            count.push_back(int(std::unique(lines.begin(), lines.end()) - lines.begin()));
            i = j;
        }
    };
    std::vector<Met> along_axes, along_diagonals;
    std::vector<Vec3> p;
    const Vec3 out[4] = {unit(b), unit(c), -unit(b), -unit(c)};
    int line = 0;
    for (const double end : {1.0, -1.0})
        for (int q = 0; q < 4; ++q, ++line) {
            for (double x : creases_along(out[q], end * unit(axis), p))
                along_axes.push_back({x, line});
            if (found.meridian.empty()) found.meridian = p;
            for (double x : creases_along(out[q] + out[(q + 1) % 4], end * unit(axis), p))
                along_diagonals.push_back({x, line});
        }
    cluster(along_axes, found.radius, found.seen);
    std::vector<double> diagonal;
    std::vector<int> diagonal_seen;
    cluster(along_diagonals, diagonal, diagonal_seen);
    // The k-th crease out along the diagonals is the k-th along the axes when they are as
    // many; otherwise each crease is taken for a circle.
    for (size_t k = 0; k < found.radius.size(); ++k)
        found.reach.push_back(diagonal.size() == found.radius.size() ? std::sqrt(2.0) * diagonal[k]
                                                                     : found.radius[k]);
    return found;
}

int choose_axis(const std::array<AxialCreases, 3>& creases) {
    int best = -1, best_count = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const AxialCreases& c = creases[axis];
        int count = 0;
        for (size_t k = 0; k < c.radius.size(); ++k)
            count += c.seen[k] >= 4 && c.reach[k] < 1.2 * c.radius[k];
        if (count > best_count) best = axis, best_count = count;
    }
    return best;
}

}  // namespace hexmesh

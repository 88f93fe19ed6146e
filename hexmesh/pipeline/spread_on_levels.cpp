// spread_on_levels: an exterior grid's lines carried out level by level, the wall grid
// repaired with the 2D functional on the levels where its gradient lines part or merge.
#include "hexmesh/pipeline/spread_on_levels.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "hexmesh/pipeline/exterior_paths.h"
#include "surface/projection.h"
#include "volume/cube_sphere.h"
#include "volume/o_h_grid.h"

namespace hexmesh {
namespace {

// The level F = c of a potential as a surface to project onto: (F - c) / |grad F|, about the
// distance to the level near it, so that projection tolerances are lengths.
class Level final : public ImplicitFunction {
  public:
    Level(const ImplicitFunction& f, double c) : f_(f), c_(c) {}
    double value(const Vec3& p) const override {
        const double g = f_.gradient(p).norm();
        return (f_.value(p) - c_) / std::max(g, 1e-300);
    }
    Vec3 gradient(const Vec3& p) const override { return f_.gradient(p).normalized(); }
    Box3 bounds() const override { return f_.bounds(); }

  private:
    const ImplicitFunction& f_;
    double c_;
};

// The lattice's quads, each quad's neighbours across its edges, and each node's quads.
struct QuadLattice {
    std::vector<std::array<Id, 4>> quads;
    std::vector<std::array<Id, 4>> across;  // quad across edge (c, c + 1), -1 if none
    std::vector<std::vector<Id>> around;    // node -> quads

    explicit QuadLattice(int n) : quads(cube_surface_quads(make_cube_surface_lattice(n))) {
        Id nodes = 0;
        for (const auto& q : quads)
            for (Id v : q) nodes = std::max(nodes, v + 1);
        around.resize(nodes);
        for (Id q = 0; q < Id(quads.size()); ++q)
            for (Id v : quads[q]) around[v].push_back(q);
        across.assign(quads.size(), {-1, -1, -1, -1});
        for (Id q = 0; q < Id(quads.size()); ++q)
            for (int c = 0; c < 4; ++c) {
                const Id a = quads[q][c], b = quads[q][(c + 1) % 4];
                for (Id r : around[a])
                    if (r != q && std::find(quads[r].begin(), quads[r].end(), b) != quads[r].end())
                        across[q][c] = r;
            }
    }
};

// A quad on a level: its size (square root of its area seen along grad F at its centre) and
// the smallest sine of its corner angles there (negative: folded).
struct QuadShape {
    double size, min_sine;
};

// The normal of the level through y: along grad F, or where that vanishes (a pocket of the
// interpolant, or past its lattice) along the ray from the centre, the level being taken as
// star-shaped there.
Vec3 level_normal(const ImplicitFunction& f, const Vec3& centre, const Vec3& y) {
    const Vec3 g = f.gradient(y);
    return g.allFinite() && g.norm() > 0 ? g : Vec3(y - centre);
}

QuadShape quad_shape(const ImplicitFunction& f, const Vec3& origin, const std::vector<Vec3>& x,
                     const std::array<Id, 4>& q) {
    const Vec3 centre = 0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]);
    const Vec3 n = level_normal(f, origin, centre).normalized();
    const double area = 0.5 * (x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]).dot(n);
    double min_sine = 1;
    for (int c = 0; c < 4; ++c) {
        const Vec3 a = x[q[(c + 1) % 4]] - x[q[c]], b = x[q[(c + 3) % 4]] - x[q[c]];
        const double ab = a.norm() * b.norm();
        min_sine = std::min(min_sine, ab > 0 ? a.cross(b).dot(n) / ab : -1.0);
    }
    if (!std::isfinite(min_sine)) min_sine = -1;
    return {std::sqrt(std::max(std::abs(area), 0.0)), min_sine};
}

constexpr double squeezed_sine = 0.1;  // a corner angle under about 6 degrees
constexpr double size_jump = 3;        // a quad this much wider or narrower than a neighbour

// The quads to repair on a level: folded, squeezed, or far from a neighbour's size.
std::vector<char> bad_quads(const QuadLattice& lattice, const std::vector<QuadShape>& shape) {
    std::vector<char> bad(shape.size(), 0);
    for (size_t q = 0; q < shape.size(); ++q) {
        if (shape[q].min_sine < squeezed_sine) bad[q] = 1;
        for (Id r : lattice.across[q])
            if (r >= 0 && shape[q].size > size_jump * shape[r].size) bad[q] = bad[r] = 1;
    }
    return bad;
}

// The quads within `rings` rings (sharing a node) of the marked ones.
std::vector<char> widen(const QuadLattice& lattice, std::vector<char> region, int rings) {
    for (int r = 0; r < rings; ++r) {
        std::vector<char> next = region;
        for (size_t q = 0; q < region.size(); ++q)
            if (region[q])
                for (Id v : lattice.quads[q])
                    for (Id t : lattice.around[v]) next[t] = 1;
        region = std::move(next);
    }
    return region;
}

// Target sizes of the region's quads: the sizes around it carried in (the log of the size
// smoothed over the region's quads, the others held), from the region's sound quads' sizes.
std::vector<double> target_sizes(const QuadLattice& lattice, const std::vector<QuadShape>& shape,
                                 const std::vector<char>& region, const std::vector<char>& bad) {
    double sum = 0;
    int count = 0;
    for (size_t q = 0; q < shape.size(); ++q)
        if (region[q] && !bad[q] && shape[q].size > 0) sum += std::log(shape[q].size), ++count;
    const double fill = count > 0 ? sum / count : 0;
    std::vector<double> log_size(shape.size());
    for (size_t q = 0; q < shape.size(); ++q)
        log_size[q] =
            (region[q] && bad[q]) || !(shape[q].size > 0) ? fill : std::log(shape[q].size);
    for (int sweep = 0; sweep < 30; ++sweep) {
        std::vector<double> next = log_size;
        for (size_t q = 0; q < shape.size(); ++q) {
            if (!region[q]) continue;
            double s = 0;
            int m = 0;
            for (Id r : lattice.across[q])
                if (r >= 0) s += log_size[r], ++m;
            if (m > 0) next[q] = s / m;
        }
        log_size = std::move(next);
    }
    std::vector<double> size(shape.size());
    for (size_t q = 0; q < shape.size(); ++q) size[q] = std::exp(log_size[q]);
    return size;
}

// Moves the nodes of the region's quads that no other quad holds on the level F = c, with the
// 2D functional (each quad's target a square of its target size). Returns the number of the
// region's quads still folded or squeezed.
Id spread_region(const ImplicitFunction& potential, double c, const Vec3& centre,
                 const QuadLattice& lattice, const std::vector<char>& region,
                 const std::vector<double>& size, std::vector<Vec3>& x,
                 const untangle::UntangleOptions& solver) {
    untangle::Problem p;
    std::unordered_map<Id, Id> local;
    std::vector<Id> global;
    const auto id = [&](Id v) {
        const auto [it, added] = local.emplace(v, Id(global.size()));
        if (added) {
            global.push_back(v);
            const bool held = std::any_of(lattice.around[v].begin(), lattice.around[v].end(),
                                          [&](Id q) { return !region[q]; });
            p.points.push_back(x[v]);
            p.kinds.push_back(held ? VertexKind::fixed : VertexKind::slip);
        }
        return it->second;
    };
    double total = 0;
    Id count = 0;
    for (size_t q = 0; q < region.size(); ++q) {
        if (!region[q]) continue;
        const auto& quad = lattice.quads[q];
        // Local ids in the order the quad's corner triangles first meet its nodes.
        const Id n0 = id(quad[0]), n1 = id(quad[1]), n3 = id(quad[3]), n2 = id(quad[2]);
        p.add_quad({n0, n1, n2, n3}, size[q], size[q]);
        total += size[q], ++count;
    }
    const Level level(potential, c);
    p.length_scale = total / std::max<Id>(count, 1);
    p.surface_normal = [&](Id, const Vec3& y) { return level_normal(potential, centre, y); };
    p.project_to_surface = [&, h = p.length_scale](Id, const Vec3& y) {
        return project_to_surface(level, y, h).point;
    };
    untangle::UntangleOptions o = solver;
    o.log = nullptr;
    o.max_optimize_iterations = std::min(o.max_optimize_iterations, 5);
    try {
        untangle::untangle_and_optimize(p, o);
    } catch (const std::exception&) {
        // No normal somewhere on the region (grad F vanishes in a pocket of the interpolant):
        // the nodes stay where their gradient lines put them.
        return Id(std::count(region.begin(), region.end(), 1));
    }
    for (size_t a = 0; a < global.size(); ++a) x[global[a]] = p.points[a];
    Id left = 0;
    for (size_t q = 0; q < region.size(); ++q)
        if (region[q] &&
            quad_shape(potential, centre, x, lattice.quads[q]).min_sine < squeezed_sine)
            ++left;
    return left;
}

// The point of path s at level c (its levels do not decrease) and the number of its points
// below c.
std::pair<Vec3, size_t> at_level(const WallPaths& paths, size_t s, double c) {
    const auto& l = paths.levels[s];
    const auto& x = paths.lines[s];
    const size_t k = std::lower_bound(l.begin(), l.end(), c) - l.begin();
    if (k == 0) return {x.front(), 0};
    if (k == l.size()) return {x.back(), k};
    const double w = l[k] > l[k - 1] ? (c - l[k - 1]) / (l[k] - l[k - 1]) : 1.0;
    return {x[k - 1] + std::clamp(w, 0.0, 1.0) * (x[k] - x[k - 1]), k};
}

}  // namespace

LevelSpreading spread_on_levels(const ImplicitFunction& potential, WallPaths& paths,
                                const untangle::UntangleOptions& solver) {
    LevelSpreading done;
    const size_t ns = paths.lines.size();
    const double c0 = paths.far_level;
    // The first level: where a typical line is a quarter of a wall edge (its first step) from
    // the wall, about the thickness of a boundary layer.
    std::vector<double> reached(ns);
    for (size_t s = 0; s < ns; ++s) reached[s] = paths.levels[s][1];
    std::nth_element(reached.begin(), reached.begin() + ns / 2, reached.end());
    const double lowest = reached[ns / 2];
    if (!(lowest > 0) || lowest >= c0 / 1.15) return done;
    const int steps = int(std::ceil(std::log(c0 / lowest) / std::log(1.15)));
    const double step = 0.25 * grid_length_scale(potential, paths.cells_per_edge);
    const QuadLattice lattice(paths.cells_per_edge);

    std::vector<std::vector<Vec3>> line(ns);  // the moved lines so far
    std::vector<std::vector<double>> line_level(ns);
    std::vector<char> moved(ns, 0);
    std::vector<Vec3> x(ns);
    for (int j = 1; j <= steps; ++j) {
        const double c = j == steps ? c0 : lowest * std::pow(c0 / lowest, double(j) / steps);
        tbb::parallel_for(size_t(0), ns, [&](size_t s) {
            if (!moved[s]) {
                x[s] = at_level(paths, s, c).first;
                return;
            }
            // Up the gradient from where the node was moved to, on to this level.
            std::vector<double> up;
            std::vector<Vec3> more = gradient_line_up(potential, line[s].back(), c, step, up);
            if (up.back() < (1 - 1e-9) * c)
                more = gradient_line_up(potential, line[s].back(), c, step, up, true);
            for (size_t k = 1; k < more.size(); ++k) {
                line[s].push_back(more[k]);
                line_level[s].push_back(std::max(up[k], line_level[s].back()));
            }
            x[s] = line[s].back();
        });
        std::vector<QuadShape> shape(lattice.quads.size());
        tbb::parallel_for(size_t(0), shape.size(), [&](size_t q) {
            shape[q] = quad_shape(potential, paths.centre, x, lattice.quads[q]);
        });
        const std::vector<char> bad = bad_quads(lattice, shape);
        const Id count = Id(std::count(bad.begin(), bad.end(), 1));
        ++done.levels;
        if (count == 0) continue;
        const std::vector<Vec3> before = x;
        Id left = count;
        for (int rings = 2; rings <= 8 && left > 0; rings *= 2) {
            const std::vector<char> region = widen(lattice, bad, rings);
            std::vector<Vec3> y = before;
            const Id still = spread_region(potential, c, paths.centre, lattice, region,
                                           target_sizes(lattice, shape, region, bad), y, solver);
            if (still == 0) left = 0, x = std::move(y);
        }
        ++(left == 0 ? done.levels_spread : done.levels_left);
        for (size_t s = 0; s < ns; ++s) {
            if ((x[s] - before[s]).norm() <= 1e-9 * step) continue;
            if (!moved[s]) {
                const size_t below = at_level(paths, s, c).second;
                line[s].assign(paths.lines[s].begin(), paths.lines[s].begin() + below);
                line_level[s].assign(paths.levels[s].begin(), paths.levels[s].begin() + below);
                line[s].push_back(x[s]);
                line_level[s].push_back(c);
                moved[s] = 1;
                ++done.lines_moved;
            } else {
                line[s].back() = x[s];
            }
        }
    }
    for (size_t s = 0; s < ns; ++s)
        if (moved[s]) {
            paths.lines[s] = std::move(line[s]);
            paths.levels[s] = std::move(line_level[s]);
        }
    return done;
}

}  // namespace hexmesh

#include "hexmesh/pipeline/sphere_map.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "surface/projection.h"
#include "surface/surface_topology.h"
#include "volume/cube_sphere.h"
#include "volume/o_h_grid.h"

namespace hexmesh {
namespace {

// The surface with points of identical coordinates merged, triangles that lost a corner to
// that and points no triangle uses dropped, and each hole capped by a fan around a new point at
// its centroid.
TriangleSurface welded_and_capped(const TriangleSurface& in) {
    TriangleSurface s;
    const std::vector<int> first = welded_ids(in.points);
    std::vector<int> id(in.points.size(), -1);
    for (const auto& t : in.triangles) {
        const std::array<int, 3> w{first[t[0]], first[t[1]], first[t[2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
        for (int p : w)
            if (id[p] < 0) id[p] = int(s.points.size()), s.points.push_back(in.points[p]);
        s.triangles.push_back({id[w[0]], id[w[1]], id[w[2]]});
    }
    // Boundary edges a -> b (as their one triangle runs them): the cap runs them b -> a.
    std::unordered_map<std::uint64_t, int> uses = edge_uses(s.triangles);
    std::unordered_map<int, int> next;  // along the boundary, reversed
    for (const auto& t : s.triangles)
        for (int e = 0; e < 3; ++e)
            if (uses[edge_key(t[e], t[(e + 1) % 3])] == 1) next[t[(e + 1) % 3]] = t[e];
    while (!next.empty()) {
        std::vector<int> loop = {next.begin()->first};
        while (true) {
            const auto it = next.find(loop.back());
            if (it == next.end()) break;
            const int to = it->second;
            next.erase(it);
            if (to == loop.front()) break;
            loop.push_back(to);
        }
        if (loop.size() < 3) continue;
        Vec3 centre = Vec3::Zero();
        for (int p : loop) centre += s.points[p] / double(loop.size());
        const int c = int(s.points.size());
        s.points.push_back(centre);
        for (size_t k = 0; k < loop.size(); ++k)
            s.triangles.push_back({loop[k], loop[(k + 1) % loop.size()], c});
    }
    return s;
}

// About `triangles` triangles of the surface, for the map: a finer surface simplified (CGAL's
// edge collapse, Lindstrom-Turk cost and placement, which keep the shape and the topology), a
// coarser one refined (CGAL's isotropic remeshing to the edge length of that many equilateral
// triangles: a CAD part's few long slivers are ill-conditioned targets). The map need not
// follow the surface's detail, only its shape: the wall nodes it places are then projected
// onto the body.
TriangleSurface resampled(const TriangleSurface& s, size_t triangles) {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
    Mesh mesh;
    std::vector<Mesh::Vertex_index> v;
    for (const Vec3& p : s.points)
        v.push_back(mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
    for (const auto& t : s.triangles)
        if (mesh.add_face(v[t[0]], v[t[1]], v[t[2]]) == Mesh::null_face())
            return s;  // not a manifold
    if (s.triangles.size() > triangles) {
        namespace SMS = CGAL::Surface_mesh_simplification;
        SMS::Count_stop_predicate<Mesh> stop(triangles * 3 / 2);  // a closed surface's edges
        SMS::edge_collapse(mesh, stop);
    } else {
        // An equilateral triangle of edge e has area sqrt(3) e^2 / 4.
        const double edge = std::sqrt(4 * surface_area(s) / (std::sqrt(3.0) * double(triangles)));
        CGAL::Polygon_mesh_processing::isotropic_remeshing(
            faces(mesh), edge, mesh, CGAL::parameters::number_of_iterations(3));
    }
    mesh.collect_garbage();
    TriangleSurface out;
    for (const auto vi : mesh.vertices()) {
        const auto& p = mesh.point(vi);
        out.points.emplace_back(p.x(), p.y(), p.z());
    }
    for (const auto f : mesh.faces()) {
        std::array<int, 3> t;
        int c = 0;
        for (const auto vi : mesh.vertices_around_face(mesh.halfedge(f))) t[c++] = int(vi.idx());
        out.triangles.push_back(t);
    }
    return out;
}

// The point farthest along `up` whose neighbours, the boundary of Tutte's disk, are joined
// by no edge but those around it: an edge across the disk's boundary (a chord) would hold a
// triangle of three boundary points, flat or turned over in the embedding.
int chord_free_pole(const TriangleSurface& s, const Vec3& up) {
    const std::unordered_map<std::uint64_t, int> edges = edge_uses(s.triangles);
    std::vector<std::vector<int>> around(s.points.size());
    for (const auto& t : s.triangles)
        for (int c = 0; c < 3; ++c) {
            around[t[c]].push_back(t[(c + 1) % 3]);
            around[t[c]].push_back(t[(c + 2) % 3]);
        }
    std::vector<int> order(s.points.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return s.points[a].dot(up) > s.points[b].dot(up); });
    for (int p : order) {
        std::vector<int>& ring = around[p];
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        // Each ring point is joined to its two ring neighbours; any more edges among them are
        // chords.
        size_t joined = 0;
        for (size_t a = 0; a < ring.size(); ++a)
            for (size_t b = a + 1; b < ring.size(); ++b)
                joined += edges.count(edge_key(ring[a], ring[b]));
        if (ring.size() >= 3 && joined == ring.size()) return p;
    }
    return order.front();
}

// The neighbours of point `pole` in the order they turn around it (triangle (pole, a, b)
// gives a -> b).
std::vector<int> pole_ring(const TriangleSurface& s, int pole) {
    // The pole's neighbours in order: triangle (pole, a, b) gives a -> b.
    std::unordered_map<int, int> after;
    for (const auto& t : s.triangles)
        for (int c = 0; c < 3; ++c)
            if (t[c] == pole) after[t[(c + 1) % 3]] = t[(c + 2) % 3];
    if (after.empty()) throw std::invalid_argument("the surface's highest point is on no triangle");
    std::vector<int> ring = {after.begin()->first};
    while (ring.size() <= after.size()) {
        const auto b = after.find(ring.back());
        if (b == after.end() || b->second == ring.front()) break;
        ring.push_back(b->second);
    }
    if (ring.size() != after.size())
        throw std::invalid_argument("the surface is not a manifold at its highest point");

    return ring;
}

// Tutte's embedding of the surface without the pole into the unit disk: the pole's ring on
// the circle, every other point the mean of its neighbours (a sparse Laplace solve).
std::vector<Eigen::Vector2d> tutte_disk(const TriangleSurface& s, int pole,
                                        const std::vector<int>& ring) {
    const int np = int(s.points.size());
    std::vector<std::vector<int>> neighbours(np);
    for (const auto& t : s.triangles)
        for (int c = 0; c < 3; ++c) {
            neighbours[t[c]].push_back(t[(c + 1) % 3]);
            neighbours[t[c]].push_back(t[(c + 2) % 3]);
        }
    for (auto& n : neighbours) {
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
    }
    std::vector<Eigen::Vector2d> plane(np, Eigen::Vector2d::Zero());
    std::vector<int> unknown(np, -1);
    for (size_t k = 0; k < ring.size(); ++k) {
        const double a = 2 * M_PI * double(k) / double(ring.size());
        plane[ring[k]] = Eigen::Vector2d(std::cos(a), std::sin(a));
        unknown[ring[k]] = -2;
    }
    unknown[pole] = -3;
    int count = 0;
    for (int p = 0; p < np; ++p)
        if (unknown[p] == -1) unknown[p] = count++;
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(count, 2);
    for (int p = 0; p < np; ++p) {
        const int row = unknown[p];
        if (row < 0) continue;
        entries.emplace_back(row, row, double(neighbours[p].size()));
        for (int q : neighbours[p]) {
            if (unknown[q] >= 0)
                entries.emplace_back(row, unknown[q], -1.0);
            else
                rhs.row(row) += plane[q].transpose();  // a ring point (the pole is no neighbour)
        }
    }
    Eigen::SparseMatrix<double> laplacian(count, count);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
    if (solver.info() != Eigen::Success)
        throw std::invalid_argument("the surface's Tutte system is singular: it is not one piece");
    const Eigen::MatrixX2d solution = solver.solve(rhs);
    for (int p = 0; p < np; ++p)
        if (unknown[p] >= 0) plane[p] = solution.row(unknown[p]).transpose();

    return plane;
}

// Tutte's embedding onto the sphere (see map_to_sphere), the pole at point `pole`.
std::vector<Vec3> tutte_on_sphere(const TriangleSurface& s, int pole) {
    const int np = int(s.points.size());
    const std::vector<int> ring = pole_ring(s, pole);
    std::vector<Eigen::Vector2d> plane = tutte_disk(s, pole, ring);
    // The inverse stereographic projection from the north pole, the ring at latitude where
    // the disk's radius rho lands: the pole's triangles form a small cap.
    constexpr double rho = 3;
    std::vector<Vec3> sphere(np);
    for (int p = 0; p < np; ++p) {
        if (p == pole) {
            sphere[p] = Vec3::UnitZ();
            continue;
        }
        const Eigen::Vector2d q = rho * plane[p];
        const double r2 = q.squaredNorm();
        sphere[p] = Vec3(2 * q.x(), 2 * q.y(), r2 - 1) / (1 + r2);
    }
    // Seen from outside the projection turns the plane over: mirror when the triangles turn
    // clockwise (negative signed volume).
    double volume = 0;
    for (const auto& t : s.triangles) volume += sphere[t[0]].dot(sphere[t[1]].cross(sphere[t[2]]));
    if (volume < 0)
        for (Vec3& p : sphere) p.x() = -p.x();
    return sphere;
}

// The functional of the map on the sphere, from the first map `sphere`: each triangle's
// target its own shape on the surface `s`, scaled so the targets cover the sphere; points
// slide on the sphere.
untangle::Problem sphere_problem(const TriangleSurface& s, std::vector<Vec3> sphere) {
    // Targets: each triangle's own shape, scaled so their areas add up to the sphere's.
    const double scale = std::sqrt(4 * M_PI / surface_area(s));
    untangle::Problem p;
    p.kinds.assign(sphere.size(), VertexKind::slip);
    p.points = std::move(sphere);
    for (const auto& t : s.triangles) {
        const Vec3 e1 = scale * (s.points[t[1]] - s.points[t[0]]);
        const Vec3 e2 = scale * (s.points[t[2]] - s.points[t[0]]);
        const double l1 = e1.norm(), twice = e1.cross(e2).norm();
        if (!(twice > 1e-12 * l1 * l1)) continue;  // no shape to keep
        Eigen::Matrix2d h;
        h << l1, e1.dot(e2) / l1, 0, twice / l1;
        untangle::TriangleTarget target;
        target.inverse = h.inverse();
        target.weight = twice / 2;
        p.triangles.push_back({t[0], t[1], t[2]});
        p.triangle_targets.push_back(target);
    }
    p.length_scale = std::sqrt(4 * M_PI / double(s.triangles.size()));
    p.surface_normal = [](Id, const Vec3& x) { return x; };
    p.project_to_surface = [](Id, const Vec3& x) { return Vec3(x.normalized()); };
    return p;
}

}  // namespace

// Triangles binned by the cells of a uniform lattice over [-1, 1]^3 their spherical triangle
// may reach.
struct SphereMap::Locator {
    static constexpr int m = 24;
    std::vector<std::vector<int>> cells = std::vector<std::vector<int>>(m * m * m);
    static int cell_of(double v) { return std::clamp(int((v + 1.02) / 2.04 * m), 0, m - 1); }
    static int cell(const Vec3& p) {
        return cell_of(p.x()) + m * (cell_of(p.y()) + m * cell_of(p.z()));
    }
};

SphereMap::SphereMap(TriangleSurface surface, std::vector<Vec3> sphere)
    : surface_(std::move(surface)),
      sphere_(std::move(sphere)),
      locator_(std::make_unique<Locator>()) {
    for (int t = 0; t < int(surface_.triangles.size()); ++t) {
        const auto& tri = surface_.triangles[t];
        const Vec3 a = sphere_[tri[0]], b = sphere_[tri[1]], c = sphere_[tri[2]];
        // The box of points spread over the spherical triangle (its sides bulge out of the
        // chord's box).
        Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
        constexpr int k = 4;
        for (int i = 0; i <= k; ++i)
            for (int j = 0; i + j <= k; ++j) {
                const Vec3 p = (double(i) * a + double(j) * b + double(k - i - j) * c).normalized();
                if (p.allFinite()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
            }
        const Vec3 pad = 0.05 * (hi - lo) + Vec3::Constant(1e-9);
        lo -= pad, hi += pad;
        for (int k = Locator::cell_of(lo.z()); k <= Locator::cell_of(hi.z()); ++k)
            for (int j = Locator::cell_of(lo.y()); j <= Locator::cell_of(hi.y()); ++j)
                for (int i = Locator::cell_of(lo.x()); i <= Locator::cell_of(hi.x()); ++i)
                    locator_->cells[i + Locator::m * (j + Locator::m * k)].push_back(t);
    }
}

SphereMap::~SphereMap() = default;
SphereMap::SphereMap(SphereMap&&) noexcept = default;

Id SphereMap::inverted() const {
    Id count = 0;
    for (const auto& t : surface_.triangles)
        count += !(sphere_[t[0]].dot(sphere_[t[1]].cross(sphere_[t[2]])) > 0);
    return count;
}

Vec3 SphereMap::surface_point(const Vec3& q) const {
    // Barycentric weights of the ray along q in triangle t: the triple products of q with its
    // edges (all >= 0 inside); the triangle with the largest smallest weight is taken, so a
    // ray through an edge or a sliver's gap still finds one.
    int best = -1;
    double best_min = -1e300;
    Eigen::Vector3d best_w;
    const auto consider = [&](int t) {
        const auto& tri = surface_.triangles[t];
        const Vec3 &a = sphere_[tri[0]], &b = sphere_[tri[1]], &c = sphere_[tri[2]];
        const Eigen::Vector3d w(q.dot(b.cross(c)), q.dot(c.cross(a)), q.dot(a.cross(b)));
        const double sum = w.sum();
        if (!(sum > 0)) return;
        const double low = w.minCoeff() / sum;
        if (low > best_min) best_min = low, best = t, best_w = w / sum;
    };
    for (int t : locator_->cells[Locator::cell(q)]) consider(t);
    if (best_min < 0)  // not inside any binned there: every triangle (a map with a fold)
        for (int t = 0; t < int(surface_.triangles.size()); ++t) consider(t);
    if (best < 0) throw std::logic_error("SphereMap: no triangle faces the direction");
    const auto& tri = surface_.triangles[best];
    best_w = best_w.cwiseMax(0.0);
    best_w /= best_w.sum();
    return best_w[0] * surface_.points[tri[0]] + best_w[1] * surface_.points[tri[1]] +
           best_w[2] * surface_.points[tri[2]];
}

SphereMap map_to_sphere(const TriangleSurface& input, const SphereMapOptions& o,
                        const std::function<Vec3(const Vec3&)>& start) {
    TriangleSurface s = resampled(welded_and_capped(input), size_t(o.triangles));
    if (s.triangles.empty()) throw std::invalid_argument("the surface has no triangle");
    if (const SurfaceTopology t = surface_topology(s); t.components.size() != 1 ||
                                                       t.components[0].euler != 2 ||
                                                       t.components[0].boundary_edges != 0)
        throw std::invalid_argument(
            fmt::format("the surface is not one closed piece of genus 0 "
                        "({} pieces, the largest with V - E + F = {})",
                        t.components.size(), t.components[0].euler));
    untangle::UntangleOptions u;
    u.optimize_solver = o.solver;
    u.theta = o.theta;
    u.max_optimize_iterations = o.iterations;
    u.regularize_below = 1e-3;
    u.log = nullptr;
    // The first map may start with triangles turned over that the functional does not repair
    // (a body with four bent limbs: 3 left from its highest point, none from its lowest):
    // then the map again with the pole at the body's other extremes, the best kept (fewest
    // triangles turned over, then lowest energy).
    std::vector<Vec3> best;
    untangle::UntangleResult best_r;
    int tried = 0;
    const Vec3 ups[] = {Vec3::UnitZ(),  -Vec3::UnitZ(), Vec3::UnitX(),
                        -Vec3::UnitX(), Vec3::UnitY(),  -Vec3::UnitY()};
    for (const Vec3& up : ups) {
        std::vector<Vec3> sphere(s.points.size());
        if (start)
            tbb::parallel_for(size_t(0), sphere.size(),
                              [&](size_t i) { sphere[i] = start(s.points[i]); });
        else
            sphere = tutte_on_sphere(s, chord_free_pole(s, up));
        untangle::Problem p = sphere_problem(s, std::move(sphere));
        const untangle::UntangleResult r = untangle::untangle_and_optimize(p, u);
        ++tried;
        if (best.empty() || r.inverted_after < best_r.inverted_after ||
            (r.inverted_after == best_r.inverted_after && r.energy_after < best_r.energy_after))
            best = std::move(p.points), best_r = r;
        if (best_r.inverted_after == 0 || start) break;
    }
    if (o.log) {
        *o.log << untangle::format_untangle_summary(best_r);
        if (tried > 1)
            *o.log << fmt::format(
                "  Tutte's map tried from {} poles (the body's highest point first, then its other "
                "extremes): {} triangles left turned over by the best\n",
                tried, best_r.inverted_after);
    }
    return SphereMap(std::move(s), std::move(best));
}

SphereMap aligned_with_body(const SphereMap& map, const Vec3& centre) {
    const TriangleSurface& s = map.surface();
    Mat3 correlation = Mat3::Zero();  // sum of area * image * direction^T
    for (const auto& t : s.triangles) {
        const double area =
            0.5 * (s.points[t[1]] - s.points[t[0]]).cross(s.points[t[2]] - s.points[t[0]]).norm();
        for (int c = 0; c < 3; ++c) {
            const Vec3 d = s.points[t[c]] - centre;
            if (d.norm() > 0) correlation += area * map.sphere()[t[c]] * d.normalized().transpose();
        }
    }
    // R maximizing trace(R correlation): V diag(1, 1, det) U^T for correlation = U S V^T.
    const Eigen::JacobiSVD<Mat3> svd(correlation, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 flip = Mat3::Identity();
    flip(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
    const Mat3 rotation = svd.matrixV() * flip * svd.matrixU().transpose();
    std::vector<Vec3> sphere(map.sphere().size());
    for (size_t i = 0; i < sphere.size(); ++i)
        sphere[i] = (rotation * map.sphere()[i]).normalized();
    return SphereMap(s, std::move(sphere));
}

Vec3 image_of_nearest(const SphereMap& map, const ExactDistance& nearest, const Vec3& x) {
    const std::array<int, 3>& t = map.surface().triangles[nearest.closest_triangle(x)];
    const Vec3 q = nearest.closest_point(x);
    const Vec3 &a = map.surface().points[t[0]], &b = map.surface().points[t[1]],
               &c = map.surface().points[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    Vec3 w = Vec3::Constant(1.0 / 3);
    if (n.squaredNorm() > 0) {
        w[0] = (c - b).cross(q - b).dot(n) / n.squaredNorm();
        w[1] = (a - c).cross(q - c).dot(n) / n.squaredNorm();
        w[2] = 1 - w[0] - w[1];
    }
    const Vec3 image =
        w[0] * map.sphere()[t[0]] + w[1] * map.sphere()[t[1]] + w[2] * map.sphere()[t[2]];
    return image.norm() > 0 ? Vec3(image.normalized()) : map.sphere()[t[0]];
}

std::vector<Vec3> wall_from_sphere_map(const SphereMap& map, int n, const ImplicitFunction& body) {
    const CubeSurfaceLattice lattice = make_cube_surface_lattice(n);
    const double h = grid_length_scale(body, n);
    std::vector<Vec3> wall(lattice.size());
    tbb::parallel_for(Id(0), lattice.size(), [&](Id s) {
        const Vec3 q = cube_sphere_ray(lattice.points[s], n, Vec3::Ones()).normalized();
        ProjectionOptions o;
        o.tolerance = 1e-12;
        wall[s] = project_to_surface(body, map.surface_point(q), h, o).point;
    });
    for (const Vec3& x : wall)
        if (!x.allFinite())
            throw std::runtime_error("a wall node placed through the sphere map is not finite");
    return wall;
}

}  // namespace hexmesh

#include "volume/tet_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>

#include <chrono>
#include <stdexcept>
#include <unordered_map>

#include "hexmesh/quality/validity.h"

namespace hexmesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using BaseDomain = CGAL::Labeled_mesh_domain_3<K>;
using Domain = CGAL::Mesh_domain_with_polyline_features_3<BaseDomain>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

Vec3 to_vec(const Point& p) {
    return {p.x(), p.y(), p.z()};
}
Point to_point(const Vec3& v) {
    return {v.x(), v.y(), v.z()};
}

// The sizing function scaled for one CGAL criterion (they bound radii, not edge lengths).
struct ScaledSize {
    const std::function<double(const Vec3&)>* size;
    double factor;
    template <typename Index>
    K::FT operator()(const Point& p, int, const Index&) const {
        return factor * (*size)(to_vec(p));
    }
};

double elapsed(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// The tets of the complex over their own point numbering, oriented positively.
PlacedTetMesh extract(const C3t3& c3t3) {
    PlacedTetMesh out;
    std::unordered_map<Tr::Vertex_handle, Id> ids;
    auto id_of = [&](Tr::Vertex_handle v) {
        auto [it, added] = ids.emplace(v, Id(out.mesh.points.size()));
        if (added) {
            out.mesh.points.push_back(to_vec(c3t3.triangulation().point(v).point()));
            out.dimension.push_back(std::int8_t(c3t3.in_dimension(v)));
        }
        return it->second;
    };
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
        std::array<Id, 4> t;
        for (int i = 0; i < 4; ++i) t[i] = id_of(c->vertex(i));
        // CGAL's cells are positively oriented already; the exact predicate makes sure.
        const auto& x = out.mesh.points;
        if (exact_orientation(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) < 0) std::swap(t[2], t[3]);
        out.mesh.tets.insert(out.mesh.tets.end(), t.begin(), t.end());
    }
    return out;
}

}  // namespace

TetMeshGeneration generate_tet_mesh(const ImplicitFunction& body, const TetMeshOptions& options) {
    const Box3 box = body.bounds();
    const Vec3 centre = box.center();
    if (!options.size) throw std::invalid_argument("generate_tet_mesh: no sizing function");
    const double h0 = options.size(centre);
    if (!(h0 > 0))
        throw std::invalid_argument("generate_tet_mesh: the sizing function must be positive");
    const double radius = 0.55 * box.diagonal() + h0;
    // Surface points found by bisection on segments, to 1e-9 of the bounding radius.
    std::function<double(const Point&)> u = [&body](const Point& p) {
        return body.value(to_vec(p));
    };
    Domain domain(
        BaseDomain::create_implicit_mesh_domain(u, K::Sphere_3(to_point(centre), radius * radius),
                                                CGAL::parameters::relative_error_bound = 1e-9));
    std::vector<std::vector<Point>> polylines;
    for (const auto& line : options.features) {
        if (line.size() < 2) continue;
        std::vector<Point> l;
        for (const Vec3& v : line) l.push_back(to_point(v));
        polylines.push_back(std::move(l));
    }
    if (!polylines.empty()) domain.add_features(polylines.begin(), polylines.end());
    std::vector<Point> corners;
    for (const Vec3& c : options.corners) corners.push_back(to_point(c));
    if (!corners.empty()) domain.add_corners(corners.begin(), corners.end());

    // A regular tet of edge a has circumradius 0.612 a, its faces 0.577 a.
    const ScaledSize edge{&options.size, 1.0}, facet{&options.size, 0.577},
        cell{&options.size, 0.612};
    const double facet_distance = options.facet_distance > 0 ? options.facet_distance : 0.1 * h0;
    namespace p = CGAL::parameters;
    const Criteria criteria(p::edge_size = edge, p::facet_angle = options.facet_angle,
                            p::facet_size = facet, p::facet_distance = facet_distance,
                            p::cell_radius_edge_ratio = options.radius_edge_ratio,
                            p::cell_size = cell);

    TetMeshGeneration result;
    const auto start = std::chrono::steady_clock::now();
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, p::features(domain), p::no_perturb(),
                                        p::no_exude(), p::no_lloyd(), p::no_odt());
    result.refined = extract(c3t3);
    result.seconds = elapsed(start);
    if (result.refined.mesh.num_cells() == 0)
        throw std::runtime_error(
            "tet mesh: refinement gave no tetrahedron; the body may be thinner than the cell size");
    if (options.cgal_sliver_removal) {
        const auto again = std::chrono::steady_clock::now();
        CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = options.cgal_time_limit,
                             p::sliver_bound = options.cgal_sliver_bound);
        CGAL::exude_mesh_3(c3t3, p::time_limit = options.cgal_time_limit, p::sliver_bound = 0);
        result.cgal_seconds = elapsed(again);
        result.cgal_optimized = extract(c3t3);
    }
    return result;
}

}  // namespace hexmesh

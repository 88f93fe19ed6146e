#include "surface/surface_diagnostics.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace hexmesh {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

bool share_point(const std::array<int, 3>& a, const std::array<int, 3>& b) {
    for (int x : a)
        if (std::find(b.begin(), b.end(), x) != b.end()) return true;
    return false;
}

long long count_self_intersections(const TriangleSurface& s, const std::vector<int>& kept) {
    std::vector<Kernel::Point_3> points;
    points.reserve(s.points.size());
    for (const Vec3& p : s.points) points.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(kept.size());
    for (int t : kept) {
        const auto& tri = s.triangles[t];
        polygons.push_back({std::size_t(tri[0]), std::size_t(tri[1]), std::size_t(tri[2])});
    }
    PMP::orient_polygon_soup(points, polygons);  // may duplicate non-manifold points
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    PMP::self_intersections<CGAL::Parallel_if_available_tag>(mesh, std::back_inserter(pairs));
    long long count = 0;
    for (const auto& [f, g] : pairs) {
        // Faces are created in polygon order; a pair sharing an input point only met at a
        // point that orient_polygon_soup duplicated.
        if (f.idx() >= kept.size() || g.idx() >= kept.size()) continue;
        const auto& a = s.triangles[kept[f.idx()]];
        const auto& b = s.triangles[kept[g.idx()]];
        if (f != g && !share_point(a, b)) ++count;
    }
    return count;
}

}  // namespace

bool is_degenerate_triangle(const TriangleSurface& s, int triangle) {
    const auto& t = s.triangles[triangle];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return true;
    const Vec3 &a = s.points[t[0]], &b = s.points[t[1]], &c = s.points[t[2]];
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    return !((b - a).cross(c - a).norm() > 1e-12 * longest);
}

SurfaceDiagnostics diagnose_surface(const TriangleSurface& s) {
    SurfaceDiagnostics d;
    d.points = (long long)s.points.size();
    d.triangles = (long long)s.triangles.size();
    d.bounds = surface_bounds(s);

    std::vector<int> kept;
    for (int t = 0; t < (int)s.triangles.size(); ++t) {
        if (!is_degenerate_triangle(s, t)) {
            kept.push_back(t);
        } else {
            ++d.degenerate_triangles;
            if (d.degenerate_ids.size() < 10) d.degenerate_ids.push_back(t);
        }
    }
    // Undirected edge -> (uses a->b with a < b, uses b->a).
    std::unordered_map<std::uint64_t, std::pair<int, int>> uses;
    uses.reserve(kept.size() * 2);
    for (int t : kept)
        for (int e = 0; e < 3; ++e) {
            const int a = s.triangles[t][e], b = s.triangles[t][(e + 1) % 3];
            auto& u = uses[edge_key(a, b)];
            (a < b ? u.first : u.second)++;
        }
    d.edges = (long long)uses.size();
    for (const auto& [edge, u] : uses) {
        const int n = u.first + u.second;
        d.boundary_edges += n == 1;
        d.non_manifold_edges += n > 2;
        d.inconsistent_edges += n == 2 && u.first != 1;
    }
    if (!kept.empty()) d.self_intersections = count_self_intersections(s, kept);
    return d;
}

std::optional<TriangleSurface> without_zero_area_triangles(const TriangleSurface& s,
                                                           long long& removed) {
    removed = 0;
    std::vector<int> degenerate;
    for (int t = 0; t < int(s.triangles.size()); ++t)
        if (is_degenerate_triangle(s, t)) degenerate.push_back(t);
    if (degenerate.empty()) return s;
    std::vector<Kernel::Point_3> points;
    points.reserve(s.points.size());
    for (const Vec3& p : s.points) points.emplace_back(p.x(), p.y(), p.z());
    std::vector<std::vector<std::size_t>> polygons;
    for (const auto& t : s.triangles)
        if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0])  // a repeated point: dropped
            polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return std::nullopt;
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    if (!PMP::remove_degenerate_faces(mesh)) return std::nullopt;
    PMP::remove_isolated_vertices(mesh);
    mesh.collect_garbage();
    TriangleSurface out;
    out.points.reserve(mesh.number_of_vertices());
    for (Mesh::Vertex_index v : mesh.vertices()) {
        const Kernel::Point_3& p = mesh.point(v);
        out.points.emplace_back(p.x(), p.y(), p.z());
    }
    for (Mesh::Face_index f : mesh.faces()) {
        std::array<int, 3> t{};
        int k = 0;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            if (k < 3) t[k++] = int(v.idx());
        if (k != 3) return std::nullopt;
        out.triangles.push_back(t);
    }
    if (out.triangles.empty()) return std::nullopt;
    for (int t = 0; t < int(out.triangles.size()); ++t)
        if (is_degenerate_triangle(out, t)) return std::nullopt;
    removed = (long long)degenerate.size();
    return out;
}

}  // namespace hexmesh

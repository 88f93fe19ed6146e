#include "surface/surface_topology.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

namespace hexmesh {
namespace {

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    }
    void join(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace

std::vector<int> welded_ids(const std::vector<Vec3>& points) {
    std::map<std::array<double, 3>, int> first;
    std::vector<int> id(points.size());
    for (size_t i = 0; i < points.size(); ++i)
        id[i] =
            first
                .emplace(std::array<double, 3>{points[i].x(), points[i].y(), points[i].z()}, int(i))
                .first->second;
    return id;
}

SurfaceTopology surface_topology(const TriangleSurface& surface) {
    SurfaceTopology topology;
    const int np = int(surface.points.size());
    const std::vector<int> weld = welded_ids(surface.points);
    std::vector<std::array<int, 3>> tris(surface.triangles.size());
    for (size_t t = 0; t < tris.size(); ++t)
        for (int c = 0; c < 3; ++c) tris[t][c] = weld[surface.triangles[t][c]];

    UnionFind points(np);
    for (const auto& t : tris) points.join(t[0], t[1]), points.join(t[1], t[2]);
    std::unordered_map<int, int> index;  // union-find root -> component
    std::vector<SurfaceComponent> comps;
    const auto component_of = [&](int point) {
        const auto [it, added] = index.emplace(points.find(point), int(comps.size()));
        if (added) comps.emplace_back();
        return it->second;
    };

    const std::unordered_map<std::uint64_t, int> edges = edge_uses(tris);
    for (const auto& t : tris) ++comps[component_of(t[0])].triangles;
    std::vector<char> used(np, 0);
    for (const auto& t : tris)
        for (int p : t) used[p] = 1;
    for (int p = 0; p < np; ++p) {
        if (!used[p]) continue;
        SurfaceComponent& c = comps[component_of(p)];
        if (c.points++ == 0) c.bounds.lo = c.bounds.hi = surface.points[p];
        c.bounds.lo = c.bounds.lo.cwiseMin(surface.points[p]);
        c.bounds.hi = c.bounds.hi.cwiseMax(surface.points[p]);
    }

    // Boundary loops: the cycle rank E - V + C of each component's graph of boundary edges.
    UnionFind boundary(np);
    std::vector<char> on_boundary(np, 0);
    for (const auto& [key, uses] : edges) {
        const int a = int(key >> 32), b = int(key & 0xffffffffu);
        SurfaceComponent& c = comps[component_of(a)];
        ++c.edges;
        if (uses > 2) ++topology.non_manifold_edges;
        if (uses != 1) continue;
        ++c.boundary_edges;
        ++c.boundary_loops;  // + E
        boundary.join(a, b);
        on_boundary[a] = on_boundary[b] = 1;
    }
    std::map<int, Box3> holes;  // boundary graph root -> bounds of its points (ordered)
    for (int p = 0; p < np; ++p) {
        if (!on_boundary[p]) continue;
        SurfaceComponent& c = comps[component_of(p)];
        --c.boundary_loops;                             // - V
        if (boundary.find(p) == p) ++c.boundary_loops;  // + C
        const auto [hole, added] = holes.try_emplace(boundary.find(p));
        if (added) hole->second.lo = hole->second.hi = surface.points[p];
        hole->second.lo = hole->second.lo.cwiseMin(surface.points[p]);
        hole->second.hi = hole->second.hi.cwiseMax(surface.points[p]);
    }
    for (const auto& [root, box] : holes) {
        SurfaceComponent& c = comps[component_of(root)];
        if (box.diagonal() > c.widest_hole)
            c.widest_hole = box.diagonal(), c.widest_hole_at = box.center();
    }
    for (SurfaceComponent& c : comps) {
        c.euler = c.points - c.edges + c.triangles;
        c.genus = std::max(0LL, (2 - c.euler - c.boundary_loops) / 2);
    }
    std::stable_sort(comps.begin(), comps.end(),
                     [](const auto& a, const auto& b) { return a.triangles > b.triangles; });
    topology.components = std::move(comps);
    return topology;
}

}  // namespace hexmesh

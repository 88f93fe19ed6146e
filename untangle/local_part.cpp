// local_part: the neighbourhood of the inverted elements, grown ring by ring, as a problem of
// its own vertices.
#include "untangle/local_part.h"

#include <algorithm>
#include <limits>
#include <memory>

namespace hexmesh::untangle {
namespace {

// f with the part's vertex ids taken to the whole's (empty stays empty).
std::function<Vec3(Id, const Vec3&)> in_whole(
    const std::function<Vec3(Id, const Vec3&)>& f,
    const std::shared_ptr<const std::vector<Id>>& global) {
    if (!f) return f;
    return [f, global](Id v, const Vec3& x) { return f((*global)[v], x); };
}

}  // namespace

bool local_part(const Problem& problem, const std::vector<std::vector<Id>>& elements_of, int rings,
                Problem& part, PartOf& of) {
    const size_t nv = problem.points.size();
    const Id ne = problem.num_elements();
    std::vector<char> in(nv, 0);
    std::vector<double> det(ne);
    for (Id e = 0; e < ne; ++e) {
        det[e] = problem.det(problem.points, e);
        if (!(det[e] > 0))
            for (Id v : problem.element(e)) in[v] = 1;
    }
    for (int r = 0; r < rings; ++r) {
        std::vector<char> grown = in;
        for (size_t v = 0; v < nv; ++v)
            if (in[v])
                for (Id e : elements_of[v])
                    for (Id w : problem.element(e)) grown[w] = 1;
        in.swap(grown);
    }
    const auto free = [&](Id v) { return in[v] && degrees_of_freedom(problem.kinds[v]) > 0; };
    const auto touches = [&](const auto& nodes) {
        return std::any_of(nodes.begin(), nodes.end(), free);
    };
    // The part's vertices: those of its elements, in the whole's order.
    std::vector<Id> local(nv, -1);
    of = PartOf{};
    of.outside = {std::numeric_limits<double>::infinity(), 0};
    // A hex's corner tets come whole: all 8 when one of its nodes is free.
    const Id corners = 8 * Id(problem.hexes.size());
    for (Id e = 0; e < ne; ++e) {
        const ElementNodes nodes = problem.element(e);
        if (e < corners ? touches(problem.hexes[e / 8]) : touches(nodes)) {
            for (Id v : nodes) local[v] = 0;
        } else {
            if (!(det[e] >= of.outside.min_det)) of.outside.min_det = det[e];  // as Assembly::stats
            of.outside.inverted += !(det[e] > 0);
        }
    }
    for (const HeldQuad& q : problem.held_quads)
        if (touches(q.nodes))
            for (Id v : q.nodes) local[v] = 0;
    part = Problem{};
    for (size_t v = 0; v < nv; ++v) {
        if (local[v] < 0) continue;
        local[v] = Id(of.global.size());
        of.global.push_back(Id(v));
        part.points.push_back(problem.points[v]);
        part.kinds.push_back(in[v] ? problem.kinds[v] : VertexKind::fixed);
    }
    const auto global = std::make_shared<const std::vector<Id>>(of.global);
    part.surface_normal = in_whole(problem.surface_normal, global);
    part.project_to_surface = in_whole(problem.project_to_surface, global);
    part.edge_tangent = in_whole(problem.edge_tangent, global);
    part.project_to_edge = in_whole(problem.project_to_edge, global);
    part.surface_value = problem.surface_value;
    part.length_scale = problem.length_scale;
    const auto renumbered = [&](auto nodes) {
        for (Id& v : nodes) v = local[v];
        return nodes;
    };
    for (size_t h = 0; h < problem.hexes.size(); ++h)
        if (touches(problem.hexes[h]))
            part.add_hex(renumbered(problem.hexes[h]), problem.hex_edges[h]);
    for (size_t t = 0; t < problem.tets.size(); ++t)
        if (touches(problem.tets[t])) {
            part.tets.push_back(renumbered(problem.tets[t]));
            part.targets.push_back(problem.targets[t]);
        }
    for (size_t t = 0; t < problem.triangles.size(); ++t)
        if (touches(problem.triangles[t])) {
            part.triangles.push_back(renumbered(problem.triangles[t]));
            part.triangle_targets.push_back(problem.triangle_targets[t]);
        }
    for (const HeldQuad& q : problem.held_quads)
        if (touches(q.nodes))
            part.held_quads.push_back({renumbered(q.nodes), q.weight, q.unit_weight});
    const bool any_free = std::any_of(part.kinds.begin(), part.kinds.end(),
                                      [](VertexKind k) { return degrees_of_freedom(k) > 0; });
    return any_free && part.num_elements() < ne / 2;
}

}  // namespace hexmesh::untangle

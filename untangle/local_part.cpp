// local_part: the neighbourhood of the inverted elements, grown ring by ring, as a problem.
#include "untangle/local_part.h"

#include <algorithm>

namespace hexmesh::untangle {

bool local_part(const Problem& problem, const std::vector<std::vector<Id>>& elements_of, int rings,
                Problem& part) {
    const size_t nv = problem.points.size();
    const Id ne = problem.num_elements();
    std::vector<char> in(nv, 0);
    for (Id e = 0; e < ne; ++e)
        if (!(problem.det(problem.points, e) > 0))
            for (Id v : problem.element(e)) in[v] = 1;
    for (int r = 0; r < rings; ++r) {
        std::vector<char> grown = in;
        for (size_t v = 0; v < nv; ++v)
            if (in[v])
                for (Id e : elements_of[v])
                    for (Id w : problem.element(e)) grown[w] = 1;
        in.swap(grown);
    }
    part.points = problem.points;
    part.kinds = problem.kinds;
    part.surface_normal = problem.surface_normal;
    part.project_to_surface = problem.project_to_surface;
    part.edge_tangent = problem.edge_tangent;
    part.project_to_edge = problem.project_to_edge;
    part.surface_value = problem.surface_value;
    part.length_scale = problem.length_scale;
    size_t free = 0;
    for (size_t v = 0; v < nv; ++v) {
        if (!in[v]) part.kinds[v] = VertexKind::fixed;
        free += in[v] && degrees_of_freedom(part.kinds[v]) > 0;
    }
    const auto touches = [&](const auto& nodes) {
        return std::any_of(nodes.begin(), nodes.end(),
                           [&](Id v) { return in[v] && degrees_of_freedom(part.kinds[v]) > 0; });
    };
    for (size_t h = 0; h < problem.hexes.size(); ++h)
        if (touches(problem.hexes[h])) part.add_hex(problem.hexes[h], problem.hex_edges[h]);
    for (size_t t = 0; t < problem.tets.size(); ++t)
        if (touches(problem.tets[t])) {
            part.tets.push_back(problem.tets[t]);
            part.targets.push_back(problem.targets[t]);
        }
    for (size_t t = 0; t < problem.triangles.size(); ++t)
        if (touches(problem.triangles[t])) {
            part.triangles.push_back(problem.triangles[t]);
            part.triangle_targets.push_back(problem.triangle_targets[t]);
        }
    for (const HeldQuad& q : problem.held_quads)
        if (touches(q.nodes)) part.held_quads.push_back(q);
    return free > 0 && part.num_elements() < ne / 2;
}

}  // namespace hexmesh::untangle

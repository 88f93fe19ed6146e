#include "untangle/constraints.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace hexmesh::untangle {

int active_directions(VertexKind kind) {
    return degrees_of_freedom(kind);
}

void check_constraints(const Problem& problem) {
    if (problem.kinds.size() != problem.points.size())
        throw std::invalid_argument("one vertex kind per point is required");
    for (VertexKind k : problem.kinds) {
        if (k == VertexKind::slip && (!problem.surface_normal || !problem.project_to_surface))
            throw std::invalid_argument("slip vertices need a surface u = 0 to slide on");
        if (k == VertexKind::feature_edge && (!problem.edge_tangent || !problem.project_to_edge))
            throw std::invalid_argument("feature-edge vertices need their crease");
    }
    if (!problem.triangles.empty() && !problem.surface_normal)
        throw std::invalid_argument("surface triangles need the normal of u = 0");
    for (const auto& t : problem.triangles)
        for (Id v : t)
            if (v < 0 || v >= Id(problem.points.size()))
                throw std::invalid_argument("element refers to a missing vertex");
            else if (problem.kinds[v] == VertexKind::interior)  // no stiffness along the normal
                throw std::invalid_argument(
                    fmt::format("a surface triangle has an interior vertex ({})", v));
    for (const auto& t : problem.triangles) {
        if (problem.triangle_normal(problem.points, t).norm() > 0.5) continue;  // unit
        const Vec3 c = (problem.points[t[0]] + problem.points[t[1]] + problem.points[t[2]]) / 3;
        throw std::runtime_error(
            fmt::format("no normal of u = 0 at the surface triangle with centroid "
                        "({:.6g}, {:.6g}, {:.6g}): grad u vanishes or is not finite there",
                        c[0], c[1], c[2]));
    }
}

std::vector<Mat3> movement_bases(const Problem& problem, const std::vector<Vec3>& x) {
    std::vector<Mat3> basis(x.size(), Mat3::Zero());
    tbb::parallel_for(size_t(0), x.size(), [&](size_t v) {
        switch (problem.kinds[v]) {
            case VertexKind::interior:
                basis[v] = Mat3::Identity();
                break;
            case VertexKind::slip: {
                const Vec3 n = problem.surface_normal(Id(v), x[v]).normalized();
                const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
                basis[v].col(0) = n.cross(helper).normalized();
                basis[v].col(1) = n.cross(basis[v].col(0));
                break;
            }
            case VertexKind::feature_edge:
                basis[v].col(0) = problem.edge_tangent(Id(v), x[v]).normalized();
                break;
            case VertexKind::corner:
            case VertexKind::fixed:
                break;
        }
    });
    return basis;
}

void project_constrained(const Problem& problem, std::vector<Vec3>& x) {
    tbb::parallel_for(size_t(0), x.size(), [&](size_t v) {
        if (problem.kinds[v] == VertexKind::slip)
            x[v] = problem.project_to_surface(Id(v), x[v]);
        else if (problem.kinds[v] == VertexKind::feature_edge)
            x[v] = problem.project_to_edge(Id(v), x[v]);
    });
}

}  // namespace hexmesh::untangle

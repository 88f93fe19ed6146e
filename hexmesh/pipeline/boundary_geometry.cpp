#include "hexmesh/pipeline/boundary_geometry.h"

#include "surface/exact_distance.h"
#include "surface/implicit_features.h"
#include "surface/projection.h"
#include "surface/sharp_features.h"

namespace hexmesh {

BoundaryGeometry BoundaryGeometry::implicit(std::shared_ptr<const ImplicitFunction> body,
                                            double h) {
    BoundaryGeometry g;
    g.kind_at_ = [body](const Vec3& x, double reach) {
        return boundary_vertex_kind(classify_surface_point(*body, x, reach));
    };
    g.normal_ = [body](const Vec3& x) { return body->gradient(x); };
    g.to_surface_ = [body, h](const Vec3& x) {
        ProjectionOptions o;
        o.tolerance = 1e-12;
        return project_to_surface(*body, x, h, o).point;
    };
    g.tangent_ = [body, h](const Vec3& x) { return crease_tangent(*body, x, 1e-3 * h); };
    g.to_crease_ = [body, h](const Vec3& x) { return project_to_crease(*body, x, h); };
    g.to_corner_ = [body, h](const Vec3& x) { return snap_to_corner(*body, x, h); };
    return g;
}

BoundaryGeometry BoundaryGeometry::triangles(const TriangleSurface& triangles,
                                             const FeatureOptions& crease_options, double) {
    auto surface = std::make_shared<const TriangleSurface>(triangles);
    auto exact = std::make_shared<const ExactDistance>(*surface);
    auto features =
        std::make_shared<const FeatureCurves>(detect_sharp_features(*surface, crease_options));
    auto creases = std::make_shared<const FeatureIndex>(*surface, *features);
    BoundaryGeometry g;
    auto nearest_corner = [surface, features](const Vec3& x) {
        int best = -1;
        for (int c : features->corners)
            if (best < 0 || (surface->points[c] - x).norm() < (surface->points[best] - x).norm())
                best = c;
        return best;
    };
    g.kind_at_ = [surface, creases, nearest_corner](const Vec3& x, double reach) {
        if (creases->empty()) return VertexKind::slip;
        const int c = nearest_corner(x);
        if (c >= 0 && (surface->points[c] - x).norm() < reach) return VertexKind::corner;
        return creases->project(x).distance < reach ? VertexKind::feature_edge : VertexKind::slip;
    };
    g.normal_ = [exact](const Vec3& x) { return exact->closest_normal(x); };
    g.to_surface_ = [exact](const Vec3& x) { return exact->closest_point(x); };
    g.tangent_ = [surface, features, creases](const Vec3& x) {
        if (creases->empty()) return Vec3(Vec3::Zero());
        const FeatureProjection f = creases->project(x);
        const auto& chain = features->chains[f.chain];
        return Vec3(surface->points[chain[f.segment + 1]] - surface->points[chain[f.segment]]);
    };
    g.to_crease_ = [creases, exact](const Vec3& x) {
        if (creases->empty()) return exact->closest_point(x);
        return creases->project(x).point;
    };
    g.to_corner_ = [surface, nearest_corner, g_to_crease = g.to_crease_](const Vec3& x) {
        const int c = nearest_corner(x);
        return c >= 0 ? surface->points[c] : g_to_crease(x);
    };
    return g;
}

Vec3 BoundaryGeometry::place(const Vec3& x, VertexKind kind) const {
    switch (kind) {
        case VertexKind::slip:
            return to_surface_(x);
        case VertexKind::feature_edge:
            return to_crease_(x);
        case VertexKind::corner:
            return to_corner_(x);
        default:
            return x;
    }
}

void BoundaryGeometry::constrain(untangle::Problem& p) const {
    p.surface_normal = [normal = normal_](Id, const Vec3& x) { return normal(x); };
    p.project_to_surface = [to = to_surface_](Id, const Vec3& x) { return to(x); };
    p.edge_tangent = [tangent = tangent_](Id, const Vec3& x) { return tangent(x); };
    p.project_to_edge = [to = to_crease_](Id, const Vec3& x) { return to(x); };
}

}  // namespace hexmesh

#include "hexmesh/pipeline/untangle_mesh.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>

#include "hexmesh/core/memory_limit.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/pipeline/make_body.h"
#include "hexmesh/pipeline/optimize_tet_mesh.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/case_file.h"
#include "io/report_page.h"
#include "io/volume_mesh_io.h"

namespace hexmesh {
namespace {

using untangle::Mat34;

// Faces used by one cell only, with their nodes in the cell's outward order.
std::vector<std::vector<Id>> boundary_faces(const VolumeMesh& mesh) {
    static constexpr int tet_faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    std::map<std::vector<Id>, std::pair<int, std::vector<Id>>> uses;
    auto add = [&](std::vector<Id> face) {
        std::vector<Id> key = face;
        std::sort(key.begin(), key.end());
        auto& entry = uses[key];
        if (entry.first++ == 0) entry.second = std::move(face);
    };
    for (Id c = 0; c < mesh.num_hexes(); ++c)
        for (const auto& f : hex_faces)
            add({mesh.hexes[8 * c + f[0]], mesh.hexes[8 * c + f[1]], mesh.hexes[8 * c + f[2]],
                 mesh.hexes[8 * c + f[3]]});
    for (Id c = 0; c < mesh.num_tets(); ++c)
        for (const auto& f : tet_faces)
            add({mesh.tets[4 * c + f[0]], mesh.tets[4 * c + f[1]], mesh.tets[4 * c + f[2]]});
    std::vector<std::vector<Id>> faces;
    for (auto& [key, entry] : uses)
        if (entry.first == 1) faces.push_back(std::move(entry.second));
    return faces;
}

// The boundary faces as a triangle surface over the mesh's own point ids.
TriangleSurface triangulate(const VolumeMesh& mesh, const std::vector<std::vector<Id>>& faces) {
    TriangleSurface s;
    s.points = mesh.points;
    for (const auto& f : faces)
        for (size_t k = 1; k + 1 < f.size(); ++k)
            s.triangles.push_back({int(f[0]), int(f[k]), int(f[k + 1])});
    return s;
}

double mean_edge_length(const Mat34& y) {
    double s = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) s += (y.col(a) - y.col(b)).norm();
    return s / 6;
}

// Box-corner targets for the 8 corner tets of every hex (cube of the hex's mean edge length),
// regular targets for tets (of the tet's mean edge length).
void add_elements(const VolumeMesh& mesh, bool uniform, untangle::Problem& p, double& total_edge,
                  Id& edges) {
    std::vector<double> size(mesh.num_hexes());
    for (Id c = 0; c < mesh.num_hexes(); ++c) {
        double h = 0;
        for (const auto& e : hex_edges)
            h += (mesh.points[mesh.hexes[8 * c + e[0]]] - mesh.points[mesh.hexes[8 * c + e[1]]])
                     .norm();
        total_edge += h;
        edges += 12;
        size[c] = h / 12;
    }
    const double mean = edges ? total_edge / edges : 1;
    for (Id c = 0; c < mesh.num_hexes(); ++c) {
        std::array<Id, 8> nodes;
        std::copy_n(mesh.hexes.begin() + 8 * c, 8, nodes.begin());
        p.add_hex(nodes, Vec3::Constant(uniform ? mean : size[c]));
    }
    for (Id c = 0; c < mesh.num_tets(); ++c) {
        Mat34 y;
        for (int a = 0; a < 4; ++a) y.col(a) = mesh.points[mesh.tets[4 * c + a]];
        const double h = mean_edge_length(y);
        total_edge += 6 * h;
        edges += 6;
        p.tets.push_back(
            {mesh.tets[4 * c], mesh.tets[4 * c + 1], mesh.tets[4 * c + 2], mesh.tets[4 * c + 3]});
        p.targets.push_back(untangle::regular_tet_target(h));
    }
}

std::vector<BlockedElement> find_blocked(const VolumeMesh& mesh, const untangle::Problem& p) {
    std::vector<BlockedElement> blocked;
    for (Id e : p.blocked_elements()) {
        if (p.is_triangle(e)) continue;  // the mesh's cells: corner tets and tets
        const bool hex = p.is_hex_corner(e);
        const Id cell = hex ? e / 8 : e - 8 * mesh.num_hexes();
        blocked.push_back({cell, hex ? int(e % 8) : 0, p.points[p.element(e)[0]]});
    }
    return blocked;
}

// The kinds of the mesh's vertices in `p` (p.length_scale set): with slip, boundary vertices
// slide on the geometry (given, the surface file's, else the mesh's own boundary triangulated),
// along its creases, or stay at its corners, and the returned geometry constrains `p`; with a
// fixed boundary they stay. The mesh's own fixed vertices stay in both modes.
std::optional<BoundaryGeometry> constrain_boundary(const VolumeMesh& mesh,
                                                   const std::vector<bool>& on_boundary,
                                                   const std::vector<std::vector<Id>>& faces,
                                                   const UntangleMeshOptions& options,
                                                   untangle::Problem& p) {
    p.kinds.assign(mesh.points.size(), VertexKind::interior);
    std::optional<BoundaryGeometry> geometry;
    if (options.boundary == BoundaryMode::slip) {
        geometry = options.geometry
                       ? *options.geometry
                       : BoundaryGeometry::triangles(
                             options.surface ? *options.surface : triangulate(mesh, faces),
                             FeatureOptions{options.feature_angle_degrees, true}, p.length_scale);
        // Boundary vertices on a crease slide along it; at a corner they stay, exactly on it.
        // A given geometry (an implicit body) is sought further: a tet mesher lays crease
        // points on chords of curved creases, some 1e-2 h off them.
        const double near = (options.geometry ? 1e-2 : 1e-3) * p.length_scale;
        for (size_t v = 0; v < mesh.points.size(); ++v) {
            if (!on_boundary[v]) continue;
            p.kinds[v] = geometry->kind_at(mesh.points[v], near);
            if (p.kinds[v] == VertexKind::corner)
                p.points[v] = geometry->place(p.points[v], VertexKind::corner);
        }
        geometry->constrain(p);
    } else {
        for (size_t v = 0; v < mesh.points.size(); ++v)
            if (on_boundary[v]) p.kinds[v] = VertexKind::fixed;
    }
    if (!mesh.fixed.empty())
        for (size_t v = 0; v < mesh.points.size(); ++v)
            p.kinds[v] = mesh.fixed[v]                             ? VertexKind::fixed
                         : options.boundary == BoundaryMode::fixed ? VertexKind::interior
                                                                   : p.kinds[v];
    return geometry;
}

// Untangles with the boundary held first (it already lies on the surface, and a fixed boundary
// is the easier problem), then lets it slip to repair what the fixed boundary could not and to
// optimize; one result for both, the tangled input as "before".
untangle::UntangleResult held_then_slip(const VolumeMesh& mesh, untangle::Problem& p,
                                        const untangle::UntangleOptions& options) {
    untangle::Problem held = p;
    for (VertexKind& k : held.kinds)
        if (k != VertexKind::interior) k = VertexKind::fixed;
    untangle::UntangleOptions first = options;
    first.max_optimize_iterations = 0;
    first.unrepairable = Id(find_blocked(mesh, held).size());
    first.stall_iterations = std::min(first.stall_iterations, 3);  // a start: slip does the rest
    const untangle::UntangleResult r = untangle::untangle_and_optimize(held, first);
    p.points = held.points;
    untangle::UntangleResult solve = untangle::untangle_and_optimize(p, options);
    solve.inverted_before = r.inverted_before;
    solve.min_det_before = r.min_det_before;
    solve.seconds += r.seconds;
    solve.history.insert(solve.history.begin(), r.history.begin(), r.history.end());
    return solve;
}

}  // namespace

UntangleMeshResult untangle_volume_mesh(VolumeMesh& mesh, const UntangleMeshOptions& options) {
    untangle::Problem p;
    p.points = mesh.points;
    double total_edge = 0;
    Id edges = 0;
    add_elements(mesh, options.uniform_target, p, total_edge, edges);
    if (options.tet_size && mesh.num_tets() > 0) {
        const auto sized = sized_tet_targets(mesh.points, mesh.tets, options.tet_size);
        std::copy(sized.begin(), sized.end(), p.targets.end() - sized.size());
    }
    p.length_scale = edges ? total_edge / edges : 1;

    const auto faces = boundary_faces(mesh);
    std::vector<bool> on_boundary(mesh.points.size(), false);
    for (const auto& f : faces)
        for (Id v : f) on_boundary[v] = true;
    UntangleMeshResult result;
    const std::optional<BoundaryGeometry> geometry =
        constrain_boundary(mesh, on_boundary, faces, options, p);
    for (VertexKind k : p.kinds) {
        result.slip_vertices += k == VertexKind::slip;
        result.feature_vertices += k == VertexKind::feature_edge;
        result.fixed_vertices += k == VertexKind::fixed || k == VertexKind::corner;
    }

    if (mesh.num_hexes() > 0) result.hex_before = measure_quality(HexMesh{mesh.points, mesh.hexes});
    result.blocked = find_blocked(mesh, p);
    if (options.boundary == BoundaryMode::slip) {
        result.solve = held_then_slip(mesh, p, options.untangle);
    } else {
        untangle::UntangleOptions o = options.untangle;
        o.unrepairable = Id(result.blocked.size());
        result.solve = untangle::untangle_and_optimize(p, o);
    }
    mesh.points = p.points;
    if (mesh.num_hexes() > 0) result.hex_after = measure_quality(HexMesh{mesh.points, mesh.hexes});
    if (geometry)
        for (size_t v = 0; v < mesh.points.size(); ++v)
            if (on_boundary[v] && (mesh.fixed.empty() || !mesh.fixed[v]))
                result.max_surface_distance = std::max(result.max_surface_distance,
                                                       geometry->surface_distance(mesh.points[v]));
    return result;
}

std::string describe_blocked(const std::vector<BlockedElement>& blocked) {
    std::string out;
    for (const BlockedElement& b : blocked)
        out += fmt::format(
            "cell {} corner {} at ({:.6g}, {:.6g}, {:.6g}): its corner tet is inverted and all "
            "four "
            "of its vertices are fixed, so no fixed-boundary method can repair it; use "
            "--boundary slip\n",
            b.cell, b.corner, b.position.x(), b.position.y(), b.position.z());
    return out;
}

void slip_on_file(const std::string& path, UntangleMeshOptions& options) {
    if (std::filesystem::path(path).extension() != ".json") {
        options.surface = read_surface_file(path);
        return;
    }
    const Case c = read_case(path);
    const Body body = make_body(c.geometry);
    options.geometry = case_boundary(c, body, tet_sizes(c, *body).wall);
    options.tet_size = tet_sizing(c, body);
}

std::vector<std::string> write_untangled_mesh(const VolumeMesh& mesh, const UntangleMeshResult& r,
                                              const std::string& path, const std::string& title,
                                              const std::string* settings_json) {
    write_volume_mesh(mesh, path);
    std::vector<std::string> written = {path};
    if (!settings_json) return written;
    ReportPage page;
    if (mesh.num_hexes() > 0) {
        const HexMesh hexes{mesh.points, mesh.hexes};
        page =
            hex_mesh_report_page(title, hexes, r.hex_after ? *r.hex_after : measure_quality(hexes));
    } else {
        const TetMesh tets{mesh.points, mesh.tets};
        page = tet_mesh_report_page(title, tets, measure_tet_quality(tets));
    }
    page.settings_json = *settings_json;
    page.peak_memory_bytes = peak_memory();
    written.push_back(write_report_beside(path, page));
    return written;
}

}  // namespace hexmesh

// The report pages of unstructured meshes, hexahedra and tetrahedra: their quality's
// histograms and worst cells, pictures of their boundary faces and cuts.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/report_page.h"

namespace hexmesh {
namespace {

// The faces of cells of `corners` corners each (8: hexes, VTK order; 4: tets),
// cells[c * corners + k], that no other cell shares, and the cells that have one.
struct BoundaryFaces {
    int corners = 8;
    std::vector<std::array<Id, 4>> faces;  // nodes; a triangle's third node repeated
    std::vector<Id> cell;                  // the cell of each
    std::vector<bool> cell_on_boundary;
};

BoundaryFaces boundary_faces(const std::vector<Id>& cells, int corners) {
    static const std::array<std::array<int, 4>, 4> tet_faces = {
        {{0, 2, 1, 1}, {0, 1, 3, 3}, {1, 2, 3, 3}, {0, 3, 2, 2}}};
    const int face_count = corners == 8 ? 6 : 4;
    const Id n = Id(cells.size()) / corners;
    const auto face_nodes = [&](Id c, int f) {
        std::array<Id, 4> ids;
        for (int m = 0; m < 4; ++m)
            ids[m] = cells[c * corners + (corners == 8 ? hex_faces[f][m] : tet_faces[f][m])];
        return ids;
    };
    const auto key = [&](std::array<Id, 4> ids) {
        if (corners == 4) ids[3] = -1;
        std::sort(ids.begin(), ids.end());
        return ids;
    };
    std::unordered_map<std::array<Id, 4>, int, ArrayHash<Id, 4>> seen;  // sorted nodes: times met
    for (Id c = 0; c < n; ++c)
        for (int f = 0; f < face_count; ++f) ++seen[key(face_nodes(c, f))];
    BoundaryFaces b;
    b.corners = corners;
    b.cell_on_boundary.assign(std::size_t(n), false);
    for (Id c = 0; c < n; ++c)
        for (int f = 0; f < face_count; ++f) {
            const std::array<Id, 4> ids = face_nodes(c, f);
            if (seen[key(ids)] != 1) continue;
            b.faces.push_back(ids);
            b.cell.push_back(c);
            b.cell_on_boundary[std::size_t(c)] = true;
        }
    return b;
}

// Says of a listed cell (id `cell`) whether it has a boundary face: marked on the boundary
// views then.
void mark_on_boundary(ReportCell& listed, Id cell, const BoundaryFaces& boundary) {
    if (!boundary.cell_on_boundary[std::size_t(cell)]) return;
    listed.on_wall = true;
    listed.where += ", on the boundary";
}

// Pictures of those cells coloured by values[c] over [lo, hi]: their boundary faces and cuts.
std::vector<Picture> draw_cells(const std::vector<Vec3>& points, const std::vector<Id>& cells,
                                const BoundaryFaces& boundary, const std::vector<double>& values,
                                double lo, double hi) {
    const Box3 box = bounds_of(points);
    GridPictures pictures(box, box, lo, hi);
    const int corners = boundary.corners;
    std::array<Vec3, 8> p;
    for (Id c = 0; c < Id(cells.size()) / corners; ++c) {
        for (int k = 0; k < corners; ++k) p[k] = points[cells[c * corners + k]];
        pictures.add_cell(p.data(), corners, values[c]);
    }
    for (std::size_t f = 0; f < boundary.faces.size(); ++f) {
        const std::array<Id, 4>& ids = boundary.faces[f];
        pictures.add_wall_face({points[ids[0]], points[ids[1]], points[ids[2]], points[ids[3]]},
                               values[boundary.cell[f]]);
    }
    return pictures.pictures();
}

}  // namespace

ReportPage hex_mesh_report_page(const std::string& title, const HexMesh& mesh,
                                const QualityReport& quality) {
    GridReport report;
    report.quality = quality;
    const std::vector<double> sj = scaled_jacobians(mesh);
    const BoundaryFaces boundary = boundary_faces(mesh.hexes, 8);
    ReportPage page = grid_report_page(title, report,
                                       draw_cells(mesh.points, mesh.hexes, boundary, sj, 0, 1), "");
    for (std::size_t r = 0; r < page.worst.size(); ++r)
        mark_on_boundary(page.worst[r], quality.worst_cells[r].cell, boundary);
    return page;
}

ReportPage tet_mesh_report_page(const std::string& title, const TetMesh& mesh,
                                const TetQualityReport& q) {
    ReportPage page;
    page.title = title;
    page.value_name = "smallest dihedral angle (degrees)";
    page.value_lo = 0;
    page.value_hi = 70.53;  // a regular tet's
    const Id n = mesh.num_cells();
    std::vector<double> angle(static_cast<std::size_t>(n)), ratio(static_cast<std::size_t>(n));
    for (Id c = 0; c < n; ++c) {
        std::array<Vec3, 4> p;
        for (int k = 0; k < 4; ++k) p[k] = mesh.points[mesh.node(c, k)];
        const std::array<double, 6> a = dihedral_angles(p);
        angle[c] = *std::min_element(a.begin(), a.end());
        ratio[c] = radius_ratio(p);
    }
    const bool valid = q.inverted == 0;
    page.summary = fmt::format(
        "{} tets: <span class=\"{}\">{}</span>; smallest dihedral angle {:.3g} degrees, "
        "{} slivers (under {:.3g} degrees).",
        n, valid && q.slivers == 0 ? "good" : "bad",
        valid ? "valid" : fmt::format("{} inverted", q.inverted), q.min_dihedral, q.slivers,
        q.sliver_degrees);
    ReportHistogram a{
        "min_dihedral", "Smallest dihedral angle of each tet", "degrees", Histogram(0, 90, 18),
        fmt::format("{} tets; a sliver is under {:.3g} degrees", n, q.sliver_degrees)};
    ReportHistogram r{"radius_ratio", "Radius ratio of each tet", "3 r / R (1: regular)",
                      Histogram(0, 1, 20), "0 for a flat or inverted tet"};
    for (Id c = 0; c < n; ++c) {
        a.bins.add(angle[c]);
        r.bins.add(ratio[c]);
    }
    page.histograms = {a, r};
    std::vector<Id> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), Id(0));
    const std::size_t listed = std::min<std::size_t>(worst_cells_listed, order.size());
    std::partial_sort(order.begin(), order.begin() + listed, order.end(), [&](Id x, Id y) {
        return angle[x] < angle[y] || (angle[x] == angle[y] && x < y);
    });
    for (std::size_t k = 0; k < listed; ++k) {
        Vec3 centre = Vec3::Zero();
        for (int m = 0; m < 4; ++m) centre += 0.25 * mesh.points[mesh.node(order[k], m)];
        page.worst.push_back({angle[order[k]], fmt::format("tet {}", order[k]), centre, false});
    }
    const BoundaryFaces boundary = boundary_faces(mesh.tets, 4);
    for (std::size_t k = 0; k < listed; ++k) mark_on_boundary(page.worst[k], order[k], boundary);
    page.pictures = draw_cells(mesh.points, mesh.tets, boundary, angle, 0, 70.53);
    return page;
}

}  // namespace hexmesh

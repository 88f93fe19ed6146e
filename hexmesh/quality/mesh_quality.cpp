// measure_quality of an unstructured hex mesh (OpenFOAM's face metrics, scaled Jacobian and
// validity in two passes over the cells, faces matched by their node ids), the cells a solver
// refuses, and one cell's margin from refusal.
//
// Face (cell c, local face f) has id 6c + f; its nodes follow hex_faces (outward from c).
// An internal face is owned by the lower cell id and, as in a polyMesh, its measures use the
// owner's point order; the neighbour sees the negated area vector.
#include "hexmesh/quality/mesh_quality.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/face_geometry.h"
#include "hexmesh/quality/quality_tally.h"

namespace hexmesh {
namespace {

using detail::add_cell;
using detail::add_internal_face;
using detail::at_90_deg_or_more;
using detail::CellGeometry;
using detail::CellStats;
using detail::face_of;
using detail::FaceGeometry;
using detail::FaceStats;
using detail::make_report;

constexpr Id no_partner = -1;
constexpr Id cells_per_task = 2048;

// One cell as the unstructured pass sees it: its nodes and, per local face, the face id
// (6 cell + local face) of the same face seen from the other cell, or no_partner.
struct CellView {
    std::array<Id, 8> nodes;
    std::array<Id, 6> partner;
};

std::array<Vec3, 4> points_of(const std::vector<Vec3>& points, const std::array<Id, 8>& nodes,
                              const std::array<int, 4>& local) {
    return {points[nodes[local[0]]], points[nodes[local[1]]], points[nodes[local[2]]],
            points[nodes[local[3]]]};
}

std::array<Id, 4> sorted_face(const std::array<Id, 8>& nodes, int f) {
    const auto& local = hex_faces[f];
    std::array<Id, 4> key = {nodes[local[0]], nodes[local[1]], nodes[local[2]], nodes[local[3]]};
    std::sort(key.begin(), key.end());
    return key;
}

// Pairs up faces that list the same four nodes: faces[i] = (sorted nodes, face id).
// Calls pair(a, b) for each matched pair; a face listed by three or more cells throws.
template <class Key, class F>
void pair_equal_faces(std::vector<std::pair<Key, Id>>& faces, F&& pair) {
    std::sort(faces.begin(), faces.end());
    for (size_t i = 0; i < faces.size();) {
        size_t j = i + 1;
        while (j < faces.size() && faces[j].first == faces[i].first) ++j;
        if (j - i > 2) {
            std::ostringstream msg;
            msg << "a face is shared by more than two cells (cells " << faces[i].second / 6 << ", "
                << faces[i + 1].second / 6 << ", " << faces[i + 2].second / 6
                << "); the mesh is not a valid hex mesh";
            throw std::invalid_argument(msg.str());
        }
        if (j - i == 2) pair(faces[i].second, faces[i + 1].second);
        i = j;
    }
}

// The cells of an unstructured mesh; faces matched by their node ids. FaceId: a 32-bit id
// when 6 #cells fits (half the memory of the per-face array), else Id.
template <class FaceId>
class MeshCells {
  public:
    explicit MeshCells(const HexMesh& mesh) : mesh_(mesh) { match_faces(); }

    Id num_cells() const { return mesh_.num_cells(); }
    const std::vector<Vec3>& points() const { return mesh_.points; }
    CellView cell(Id c) const {
        CellView v;
        for (int k = 0; k < 8; ++k) v.nodes[k] = mesh_.node(c, k);
        for (int f = 0; f < 6; ++f) {
            const FaceId other = partner_[6 * c + f];
            v.partner[f] = other == FaceId(no_partner) ? no_partner : Id(other);
        }
        return v;
    }
    std::array<Vec3, 4> face_points(Id face) const {
        return points_of(mesh_.points, cell(face / 6).nodes, hex_faces[face % 6]);
    }

  private:
    // Faces are bucketed by their smallest node id (a counting sort, linear time), then
    // matched by their sorted node quadruple inside each bucket; buckets hold a handful.
    void match_faces() {
        const Id num_faces = 6 * mesh_.num_cells();
        auto smallest = [&](Id f) {
            Id n = mesh_.node(f / 6, hex_faces[f % 6][0]);
            for (int k = 1; k < 4; ++k) n = std::min(n, mesh_.node(f / 6, hex_faces[f % 6][k]));
            return n;
        };
        std::vector<Id> start(static_cast<size_t>(mesh_.num_points()) + 1, 0);
        for (Id f = 0; f < num_faces; ++f) ++start[smallest(f) + 1];
        for (size_t n = 1; n < start.size(); ++n) start[n] += start[n - 1];
        std::vector<FaceId> bucketed(static_cast<size_t>(num_faces));
        {
            std::vector<Id> fill(start.begin(), start.end() - 1);
            for (Id f = 0; f < num_faces; ++f) bucketed[fill[smallest(f)]++] = FaceId(f);
        }
        partner_.assign(static_cast<size_t>(num_faces), FaceId(no_partner));
        tbb::parallel_for(tbb::blocked_range<Id>(0, mesh_.num_points(), 1024), [&](const auto& r) {
            std::vector<std::pair<std::array<Id, 4>, Id>> bucket;
            for (Id n = r.begin(); n != r.end(); ++n) {
                bucket.clear();
                for (Id s = start[n]; s < start[n + 1]; ++s) {
                    const Id f = bucketed[s];
                    std::array<Id, 8> nodes;
                    for (int k = 0; k < 8; ++k) nodes[k] = mesh_.node(f / 6, k);
                    bucket.emplace_back(sorted_face(nodes, int(f % 6)), f);
                }
                pair_equal_faces(bucket, [&](Id a, Id b) {
                    partner_[a] = FaceId(b);
                    partner_[b] = FaceId(a);
                });
            }
        });
    }

    const HexMesh& mesh_;
    std::vector<FaceId> partner_;  // per face id
};

bool is_owner_side(Id face, Id other) {
    return other == no_partner || other / 6 > face / 6;
}

// Geometry of local face f of a cell as seen from it: computed from the owner's point
// order, the area negated on the neighbour side.
template <class Cells>
FaceGeometry oriented_face(const Cells& cells, Id c, const CellView& v, int f) {
    const Id other = v.partner[f];
    if (is_owner_side(6 * c + f, other))
        return detail::quad_geometry(points_of(cells.points(), v.nodes, hex_faces[f]));
    FaceGeometry g = detail::quad_geometry(cells.face_points(other));
    g.area = -g.area;
    return g;
}

// Cell c's faces as it sees them, its OpenFOAM centre and volume (returned) and its per-cell
// measures into `acc`.
template <class Cells>
CellGeometry measure_cell(const Cells& cells, Id c, CellStats& acc) {
    const CellView v = cells.cell(c);
    std::array<FaceGeometry, 6> faces;
    for (int f = 0; f < 6; ++f) faces[f] = oriented_face(cells, c, v, f);
    const CellGeometry g = detail::cell_geometry(faces);
    std::array<Vec3, 8> p;
    for (int k = 0; k < 8; ++k) p[k] = cells.points()[v.nodes[k]];
    add_cell(acc, c, faces, g, p);
    return g;
}

template <class Cells>
QualityReport measure(const Cells& cells) {
    QualityReport report;
    report.cells = cells.num_cells();
    if (report.cells == 0) return report;

    const std::vector<Vec3>& points = cells.points();
    std::vector<Vec3> centres(static_cast<size_t>(report.cells));
    std::vector<double> volumes(static_cast<size_t>(report.cells));

    // Pass 1, per cell: OpenFOAM centre and volume, aspect ratio, scaled Jacobian, validity.
    // The deterministic reduce splits the range the same way every run, so the sum is stable.
    const CellStats per_cell = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<Id>(0, report.cells, cells_per_task), CellStats{},
        [&](const tbb::blocked_range<Id>& r, CellStats acc) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                const CellGeometry g = measure_cell(cells, c, acc);
                centres[c] = g.centre;
                volumes[c] = g.volume;
            }
            return acc;
        },
        [](CellStats x, const CellStats& y) {
            x.join(y);
            return x;
        });

    // Pass 2, per face on its owner side: non-orthogonality, skewness, volume ratio.
    const FaceStats per_face = tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, report.cells, cells_per_task), FaceStats{},
        [&](const tbb::blocked_range<Id>& r, FaceStats acc) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                const CellView v = cells.cell(c);
                for (int f = 0; f < 6; ++f) {
                    const Id other = v.partner[f];
                    if (!is_owner_side(6 * c + f, other)) continue;
                    const std::array<Vec3, 4> p = points_of(points, v.nodes, hex_faces[f]);
                    const FaceGeometry g = detail::quad_geometry(p);
                    if (other == no_partner) {
                        acc.add_skewness(detail::boundary_face_skewness(p, g, centres[c]));
                        continue;
                    }
                    const Id n = other / 6;
                    add_internal_face(acc, p, g, centres[c], centres[n], volumes[c], volumes[n]);
                }
            }
            return acc;
        },
        [](FaceStats x, const FaceStats& y) {
            x.join(y);
            return x;
        });

    return make_report(report.cells, per_cell, per_face);
}

// The cells of `cells` failing a check of QualityReport::solver_valid, ascending: a corner tet
// inverted, a face pyramid of negative volume against its own centre, volume <= 0, a face at
// 90 degrees or more with a neighbour (then both cells) or a face of skewness over 4 (its
// cells).
template <class Cells>
std::vector<Id> refused(const Cells& cells) {
    const Id n = cells.num_cells();
    const std::vector<Vec3>& points = cells.points();
    std::vector<Vec3> centres(static_cast<size_t>(n));
    std::vector<char> bad(static_cast<size_t>(n), 0);
    tbb::parallel_for(
        tbb::blocked_range<Id>(0, n, cells_per_task), [&](const tbb::blocked_range<Id>& r) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                CellStats one;
                centres[c] = measure_cell(cells, c, one).centre;
                bad[c] = one.inverted_tets + one.negative_pyramids + one.nonpositive_volumes > 0;
            }
        });
    for (Id c = 0; c < n; ++c) {  // each face once, from its owner
        const CellView v = cells.cell(c);
        for (int f = 0; f < 6; ++f) {
            const Id other = v.partner[f];
            if (!is_owner_side(6 * c + f, other)) continue;
            const std::array<Vec3, 4> p = points_of(points, v.nodes, hex_faces[f]);
            const FaceGeometry g = detail::quad_geometry(p);
            if (other == no_partner) {
                if (detail::boundary_face_skewness(p, g, centres[c]) > max_solver_skewness)
                    bad[c] = 1;
                continue;
            }
            const Vec3& own = centres[c];
            const Vec3& nei = centres[other / 6];
            if (at_90_deg_or_more(detail::face_orthogonality(own, nei, g.area)) ||
                detail::face_skewness(p, g, own, nei) > max_solver_skewness)
                bad[c] = bad[other / 6] = 1;
        }
    }
    std::vector<Id> ids;
    for (Id c = 0; c < n; ++c)
        if (bad[c]) ids.push_back(c);
    return ids;
}

// f(MeshCells of `mesh`), with 32-bit face ids when 6 #cells fits.
template <class F>
auto with_mesh_cells(const HexMesh& mesh, F&& f) {
    if (6 * mesh.num_cells() <= Id(std::numeric_limits<std::int32_t>::max()))
        return f(MeshCells<std::int32_t>(mesh));
    return f(MeshCells<Id>(mesh));
}

}  // namespace

std::vector<Id> find_refused_cells(const HexMesh& mesh) {
    return with_mesh_cells(mesh, [](const auto& cells) { return refused(cells); });
}

QualityReport measure_quality(const HexMesh& mesh) {
    return with_mesh_cells(mesh, [](const auto& cells) { return measure(cells); });
}

namespace {

// The 6 faces of the hex p (VTK order) as it sees them: hex_faces order, outward areas.
std::array<FaceGeometry, 6> hex_face_geometries(const std::array<Vec3, 8>& p) {
    std::array<FaceGeometry, 6> faces;
    for (int f = 0; f < 6; ++f) faces[f] = detail::quad_geometry(face_of(p, hex_faces[f]));
    return faces;
}

}  // namespace

Vec3 hex_centre(const std::array<Vec3, 8>& p) {
    return detail::cell_geometry(hex_face_geometries(p)).centre;
}

double hex_face_skewness(const std::array<Vec3, 8>& p, int f, const Vec3& centre,
                         const Vec3* across) {
    const std::array<Vec3, 4> face = face_of(p, hex_faces[f]);
    const FaceGeometry g = detail::quad_geometry(face);
    return across ? detail::face_skewness(face, g, centre, *across)
                  : detail::boundary_face_skewness(face, g, centre);
}

std::vector<Id> face_neighbours(const HexMesh& mesh) {
    return with_mesh_cells(mesh, [](const auto& cells) {
        std::vector<Id> across(static_cast<size_t>(6 * cells.num_cells()), -1);
        for (Id c = 0; c < cells.num_cells(); ++c) {
            const CellView v = cells.cell(c);
            for (int f = 0; f < 6; ++f)
                if (v.partner[f] != no_partner) across[6 * c + f] = v.partner[f] / 6;
        }
        return across;
    });
}

std::array<double, 14> solver_margins(const std::array<Vec3, 8>& p) {
    std::array<double, 14> terms;
    double edges = 0;
    for (const auto& e : hex_edges) edges += (p[e[1]] - p[e[0]]).norm();
    const double mean_edge = edges / 12;
    for (int k = 0; k < 8; ++k) {
        const auto& t = hex_corner_tets[k];
        const Vec3 a = p[t[1]] - p[t[0]], b = p[t[2]] - p[t[0]], d = p[t[3]] - p[t[0]];
        const double lengths = a.norm() * b.norm() * d.norm();
        terms[k] = lengths > 0 ? a.cross(b).dot(d) / lengths : -1.0;
    }
    const std::array<FaceGeometry, 6> faces = hex_face_geometries(p);
    const CellGeometry cell = detail::cell_geometry(faces);
    for (int f = 0; f < 6; ++f) {
        const double area = faces[f].area.norm();
        terms[8 + f] = area > 0 && mean_edge > 0
                           ? faces[f].area.dot(faces[f].centre - cell.centre) / (area * mean_edge)
                           : -1.0;
    }
    return terms;
}

double solver_margin(const std::array<Vec3, 8>& p) {
    double margin = std::numeric_limits<double>::infinity();
    for (const double t : solver_margins(p)) margin = std::min(margin, t);
    return margin;
}

}  // namespace hexmesh

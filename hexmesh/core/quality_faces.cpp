// measure_quality: face matching, OpenFOAM's face metrics, scaled Jacobian and validity.
//
// Face (cell c, local face f) has id 6c + f; its nodes follow hex_faces (outward from c).
// An internal face is owned by the lower cell id and, as in a polyMesh, its geometry is
// computed once from the owner's point order; the neighbour sees the negated area vector.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hexmesh/core/face_geometry.h"
#include "hexmesh/core/quality.h"
#include "hexmesh/core/reference_hex.h"

namespace hexmesh {
namespace {

using detail::CellGeometry;
using detail::FaceGeometry;

constexpr Id no_partner = -1;

std::array<Id, 4> face_nodes(const HexMesh& mesh, Id face) {
    const Id cell = face / 6;
    const auto& local = hex_faces[face % 6];
    return {mesh.node(cell, local[0]), mesh.node(cell, local[1]), mesh.node(cell, local[2]),
            mesh.node(cell, local[3])};
}

std::array<Id, 4> sorted_key(const HexMesh& mesh, Id face) {
    std::array<Id, 4> key = face_nodes(mesh, face);
    std::sort(key.begin(), key.end());
    return key;
}

std::array<Vec3, 4> face_points(const HexMesh& mesh, Id face) {
    const std::array<Id, 4> n = face_nodes(mesh, face);
    return {mesh.points[n[0]], mesh.points[n[1]], mesh.points[n[2]], mesh.points[n[3]]};
}

// partner[face] = the same face seen from the other cell, or no_partner on the boundary.
// Faces are bucketed by their smallest node id (a counting sort, linear time), then matched
// by their sorted node quadruple inside each bucket; buckets hold a handful of faces.
// Face f = 6 cell + local face -> the face it meets (no_partner on the boundary). FaceId: a
// 32-bit id when 6 #cells fits (half the memory of these per-face arrays), else Id.
template <class FaceId>
std::vector<FaceId> match_faces(const HexMesh& mesh) {
    const Id num_faces = 6 * mesh.num_cells();
    std::vector<Id> start(static_cast<size_t>(mesh.num_points()) + 1, 0);
    for (Id f = 0; f < num_faces; ++f) ++start[sorted_key(mesh, f)[0] + 1];
    for (size_t n = 1; n < start.size(); ++n) start[n] += start[n - 1];
    std::vector<FaceId> bucketed(static_cast<size_t>(num_faces));
    {
        std::vector<Id> fill(start.begin(), start.end() - 1);
        for (Id f = 0; f < num_faces; ++f) bucketed[fill[sorted_key(mesh, f)[0]]++] = FaceId(f);
    }

    std::vector<FaceId> partner(static_cast<size_t>(num_faces), FaceId(no_partner));
    tbb::parallel_for(tbb::blocked_range<Id>(0, mesh.num_points(), 1024), [&](const auto& r) {
        std::vector<std::pair<std::array<Id, 4>, Id>> bucket;
        for (Id n = r.begin(); n != r.end(); ++n) {
            bucket.clear();
            for (Id s = start[n]; s < start[n + 1]; ++s)
                bucket.emplace_back(sorted_key(mesh, bucketed[s]), bucketed[s]);
            std::sort(bucket.begin(), bucket.end());
            for (size_t i = 0; i < bucket.size();) {
                size_t j = i + 1;
                while (j < bucket.size() && bucket[j].first == bucket[i].first) ++j;
                if (j - i > 2) {
                    std::ostringstream msg;
                    msg << "measure_quality: a face is shared by more than two cells (cells "
                        << bucket[i].second / 6 << ", " << bucket[i + 1].second / 6 << ", "
                        << bucket[i + 2].second / 6 << "); the mesh is not a valid hex mesh";
                    throw std::invalid_argument(msg.str());
                }
                if (j - i == 2) {
                    partner[bucket[i].second] = FaceId(bucket[i + 1].second);
                    partner[bucket[i + 1].second] = FaceId(bucket[i].second);
                }
                i = j;
            }
        }
    });
    return partner;
}

bool is_owner_side(Id face, Id other) {
    return other == no_partner || other / 6 > face / 6;
}

// Geometry of a face as seen from its own cell: computed from the owner's point order, the
// area negated on the neighbour side.
template <class FaceId>
FaceGeometry oriented_face(const HexMesh& mesh, const std::vector<FaceId>& partner, Id face) {
    const Id other = partner[face];
    if (is_owner_side(face, other)) return detail::quad_geometry(face_points(mesh, face));
    FaceGeometry g = detail::quad_geometry(face_points(mesh, other));
    g.area = -g.area;
    return g;
}

// Per-cell reductions of the first pass.
struct CellStats {
    double min_sj = std::numeric_limits<double>::infinity();
    double sum_sj = 0;
    double max_aspect = 0;
    double min_volume = std::numeric_limits<double>::infinity();
    Id inverted_tets = 0, inverted_cells = 0;

    void join(const CellStats& o) {
        min_sj = std::min(min_sj, o.min_sj);
        sum_sj += o.sum_sj;
        max_aspect = std::max(max_aspect, o.max_aspect);
        min_volume = std::min(min_volume, o.min_volume);
        inverted_tets += o.inverted_tets;
        inverted_cells += o.inverted_cells;
    }
};

// Per-face reductions of the second pass.
struct FaceStats {
    double min_ortho = 1;  // cosine of the largest non-orthogonality angle
    double max_skew = 0;
    double max_volume_ratio = 1;

    void join(const FaceStats& o) {
        min_ortho = std::min(min_ortho, o.min_ortho);
        max_skew = std::max(max_skew, o.max_skew);
        max_volume_ratio = std::max(max_volume_ratio, o.max_volume_ratio);
    }
};

constexpr Id cells_per_task = 2048;
constexpr double pi = 3.14159265358979323846;

}  // namespace

namespace {

template <class FaceId>
QualityReport measure(const HexMesh& mesh) {
    QualityReport report;
    report.cells = mesh.num_cells();
    if (report.cells == 0) return report;

    const std::vector<FaceId> partner = match_faces<FaceId>(mesh);
    std::vector<Vec3> centres(static_cast<size_t>(report.cells));
    std::vector<double> volumes(static_cast<size_t>(report.cells));

    // Pass 1, per cell: OpenFOAM centre and volume, aspect ratio, scaled Jacobian, validity.
    // The deterministic reduce splits the range the same way every run, so the sum is stable.
    const CellStats cells = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<Id>(0, report.cells, cells_per_task), CellStats{},
        [&](const tbb::blocked_range<Id>& r, CellStats acc) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                std::array<FaceGeometry, 6> faces;
                for (int f = 0; f < 6; ++f) faces[f] = oriented_face(mesh, partner, 6 * c + f);
                const CellGeometry g = detail::cell_geometry(faces);
                centres[c] = g.centre;
                volumes[c] = g.volume;
                acc.max_aspect =
                    std::max(acc.max_aspect, detail::cell_aspect_ratio(faces, g.volume));
                acc.min_volume = std::min(acc.min_volume, g.volume);

                const std::array<Vec3, 8> p = mesh.corners(c);
                const double sj = hex_scaled_jacobian(p);
                acc.min_sj = std::min(acc.min_sj, sj);
                acc.sum_sj += sj;
                const int inverted = count_inverted_corner_tets(p);
                acc.inverted_tets += inverted;
                acc.inverted_cells += inverted > 0;
            }
            return acc;
        },
        [](CellStats x, const CellStats& y) {
            x.join(y);
            return x;
        });

    // Pass 2, per face on its owner side: non-orthogonality, skewness, volume ratio.
    const FaceStats faces = tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, report.cells, cells_per_task), FaceStats{},
        [&](const tbb::blocked_range<Id>& r, FaceStats acc) {
            for (Id c = r.begin(); c != r.end(); ++c) {
                for (Id face = 6 * c; face < 6 * c + 6; ++face) {
                    const Id other = partner[face];
                    if (!is_owner_side(face, other)) continue;
                    const std::array<Vec3, 4> p = face_points(mesh, face);
                    const FaceGeometry g = detail::quad_geometry(p);
                    if (other == no_partner) {
                        acc.max_skew = std::max(acc.max_skew,
                                                detail::boundary_face_skewness(p, g, centres[c]));
                        continue;
                    }
                    const Id n = other / 6;
                    acc.min_ortho = std::min(
                        acc.min_ortho, detail::face_orthogonality(centres[c], centres[n], g.area));
                    acc.max_skew =
                        std::max(acc.max_skew, detail::face_skewness(p, g, centres[c], centres[n]));
                    const double vo = std::abs(volumes[c]), vn = std::abs(volumes[n]);
                    const double ratio =
                        std::max(vo, vn) / std::max(std::min(vo, vn), detail::foam_rootvsmall);
                    acc.max_volume_ratio = std::max(acc.max_volume_ratio, ratio);
                }
            }
            return acc;
        },
        [](FaceStats x, const FaceStats& y) {
            x.join(y);
            return x;
        });

    report.inverted_corner_tets = cells.inverted_tets;
    report.inverted_cells = cells.inverted_cells;
    report.min_scaled_jacobian = cells.min_sj;
    report.mean_scaled_jacobian = cells.sum_sj / static_cast<double>(report.cells);
    report.max_aspect_ratio = cells.max_aspect;
    report.min_volume = cells.min_volume;
    report.max_skewness = faces.max_skew;
    // checkMesh: acos of the smallest cosine, clamped to [-1, 1], in degrees.
    report.max_non_orthogonality_deg =
        std::acos(std::clamp(faces.min_ortho, -1.0, 1.0)) * 180.0 / pi;
    report.max_volume_ratio = faces.max_volume_ratio;
    return report;
}

}  // namespace

QualityReport measure_quality(const HexMesh& mesh) {
    if (6 * mesh.num_cells() <= Id(std::numeric_limits<std::int32_t>::max()))
        return measure<std::int32_t>(mesh);
    return measure<Id>(mesh);
}

}  // namespace hexmesh

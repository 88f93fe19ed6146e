// The per-cell and per-face measures that both measure_quality passes tally, and the report.
#include "hexmesh/quality/quality_tally.h"

#include <cmath>

#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/validity.h"

namespace hexmesh::detail {
namespace {

constexpr double pi = 3.14159265358979323846;

}  // namespace

QualityReport make_report(Id cells, const CellStats& per_cell, const FaceStats& per_face) {
    QualityReport report;
    report.cells = cells;
    report.inverted_corner_tets = per_cell.inverted_tets;
    report.inverted_cells = per_cell.inverted_cells;
    report.min_scaled_jacobian = per_cell.min_sj;
    report.worst_cell = per_cell.worst;
    report.worst_cell_centre = per_cell.worst_centre;
    report.mean_scaled_jacobian = per_cell.sum_sj / static_cast<double>(cells);
    report.max_aspect_ratio = per_cell.max_aspect;
    report.min_volume = per_cell.min_volume;
    report.max_skewness = per_face.max_skew;
    // checkMesh: acos of the smallest cosine, clamped to [-1, 1], in degrees.
    report.max_non_orthogonality_deg =
        std::acos(std::clamp(per_face.min_ortho, -1.0, 1.0)) * 180.0 / pi;
    report.max_volume_ratio = per_face.max_volume_ratio;
    report.negative_pyramids = per_cell.negative_pyramids;
    report.faces_over_90_deg = per_face.over_90_deg;
    report.highly_skewed_faces = per_face.over_skew;
    report.high_aspect_ratio_cells = per_cell.high_aspect;
    report.nonpositive_volumes = per_cell.nonpositive_volumes;
    report.worst_cells = per_cell.lowest;
    report.scaled_jacobian_histogram = per_cell.sj_histogram;
    report.non_orthogonality_histogram = per_face.non_orthogonality;
    report.internal_faces = per_face.non_orthogonality.total();
    return report;
}

// The per-cell part of the first pass: aspect ratio, volume, scaled Jacobian, validity.
void add_cell(CellStats& acc, Id cell, const std::array<FaceGeometry, 6>& faces,
              const CellGeometry& g, const std::array<Vec3, 8>& p) {
    const double aspect = detail::cell_aspect_ratio(faces, g.volume);
    acc.max_aspect = std::max(acc.max_aspect, aspect);
    acc.high_aspect += aspect > checkmesh_max_aspect_ratio;
    acc.min_volume = std::min(acc.min_volume, g.volume);
    acc.nonpositive_volumes += !(g.volume >= detail::foam_vsmall);
    // checkMesh's face pyramids: each face (outward area vector, centre) against this cell's
    // centre, a third of area . (face centre - cell centre) at least -SMALL.
    for (const FaceGeometry& f : faces)
        acc.negative_pyramids += !(f.area.dot(f.centre - g.centre) / 3 >= -detail::foam_small);
    const double sj = hex_scaled_jacobian(p);
    acc.offer_cell(sj, cell, g.centre);
    acc.sum_sj +=
        std::clamp(sj, -1.0, 1.0);  // Verdict's 1e30 for a zero-length edge would swamp the mean
    acc.sj_histogram.add(sj);
    const int inverted = count_inverted_corner_tets(p);
    acc.inverted_tets += inverted;
    acc.inverted_cells += inverted > 0;
}

// checkMesh's non-orthogonality error: the face's cosine (face_orthogonality) at most SMALL.
bool at_90_deg_or_more(double ortho) {
    return !(ortho > detail::foam_small);
}

// The second pass's measures of an internal face: p, g as its owner sees it.
void add_internal_face(FaceStats& acc, const std::array<Vec3, 4>& p, const FaceGeometry& g,
                       const Vec3& own_cc, const Vec3& nei_cc, double own_volume,
                       double nei_volume) {
    const double ortho = detail::face_orthogonality(own_cc, nei_cc, g.area);
    acc.min_ortho = std::min(acc.min_ortho, ortho);
    acc.over_90_deg += at_90_deg_or_more(ortho);
    // In degrees as max_non_orthogonality_deg; a face checkMesh counts at 90 or more is there.
    const double deg = std::acos(std::clamp(ortho, -1.0, 1.0)) * 180.0 / pi;
    acc.non_orthogonality.add(at_90_deg_or_more(ortho) ? std::max(deg, 90.0)
                                                       : std::min(deg, 89.999));
    acc.add_skewness(detail::face_skewness(p, g, own_cc, nei_cc));
    const double vo = std::abs(own_volume), vn = std::abs(nei_volume);
    const double ratio = std::max(vo, vn) / std::max(std::min(vo, vn), detail::foam_rootvsmall);
    acc.max_volume_ratio = std::max(acc.max_volume_ratio, ratio);
}

}  // namespace hexmesh::detail

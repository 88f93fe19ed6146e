// Private to hexmesh/quality: the per-cell and per-face tallies that both measure_quality
// passes (an unstructured mesh, a block grid) reduce into, and the QualityReport made of them.
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "hexmesh/core/histogram.h"
#include "hexmesh/core/types.h"
#include "hexmesh/quality/face_geometry.h"
#include "hexmesh/quality/mesh_quality.h"

namespace hexmesh::detail {

// Per-cell reductions of the first pass.
struct CellStats {
    double min_sj = std::numeric_limits<double>::infinity();
    Id worst = -1;  // the cell of min_sj (the lowest id among equals), and its centre
    Vec3 worst_centre = Vec3::Zero();
    double sum_sj = 0;
    double max_aspect = 0;
    double min_volume = std::numeric_limits<double>::infinity();
    Id inverted_tets = 0, inverted_cells = 0;
    Id negative_pyramids = 0, nonpositive_volumes = 0;
    Id high_aspect = 0;  // cells over checkmesh_max_aspect_ratio
    Histogram sj_histogram = scaled_jacobian_bins();
    std::vector<RankedCell>
        lowest;  // ascending by (scaled Jacobian, id), at most worst_cells_listed

    // A cell's scaled Jacobian: the worst so far, one of the lowest.
    void offer_cell(double sj, Id cell, const Vec3& centre) {
        offer_worst(sj, cell, centre);
        offer_lowest(RankedCell{cell, sj, centre});
    }
    void offer_worst(double sj, Id cell, const Vec3& centre) {
        if (sj < min_sj || (sj == min_sj && cell < worst))
            min_sj = sj, worst = cell, worst_centre = centre;
    }
    void offer_lowest(const RankedCell& r) {
        const auto before = [](const RankedCell& a, const RankedCell& b) {
            return a.scaled_jacobian < b.scaled_jacobian ||
                   (a.scaled_jacobian == b.scaled_jacobian && a.cell < b.cell);
        };
        if (lowest.size() == worst_cells_listed && !before(r, lowest.back())) return;
        lowest.insert(std::upper_bound(lowest.begin(), lowest.end(), r, before), r);
        if (lowest.size() > worst_cells_listed) lowest.pop_back();
    }
    void join(const CellStats& o) {
        if (o.worst >= 0) offer_worst(o.min_sj, o.worst, o.worst_centre);
        for (const RankedCell& r : o.lowest) offer_lowest(r);
        sj_histogram.join(o.sj_histogram);
        sum_sj += o.sum_sj;
        max_aspect = std::max(max_aspect, o.max_aspect);
        min_volume = std::min(min_volume, o.min_volume);
        inverted_tets += o.inverted_tets;
        inverted_cells += o.inverted_cells;
        negative_pyramids += o.negative_pyramids;
        nonpositive_volumes += o.nonpositive_volumes;
        high_aspect += o.high_aspect;
    }
};

// Per-face reductions of the second pass.
struct FaceStats {
    double min_ortho = 1;  // cosine of the largest non-orthogonality angle
    double max_skew = 0;
    double max_volume_ratio = 1;
    Id over_90_deg = 0;  // internal faces whose cosine is at most OpenFOAM's SMALL
    Id over_skew = 0;    // faces, internal or boundary, over max_solver_skewness
    Histogram non_orthogonality = non_orthogonality_bins();

    // A face's skewness (face_skewness or boundary_face_skewness).
    void add_skewness(double skew) {
        max_skew = std::max(max_skew, skew);
        over_skew += skew > max_solver_skewness;
    }
    void join(const FaceStats& o) {
        over_90_deg += o.over_90_deg;
        over_skew += o.over_skew;
        non_orthogonality.join(o.non_orthogonality);
        min_ortho = std::min(min_ortho, o.min_ortho);
        max_skew = std::max(max_skew, o.max_skew);
        max_volume_ratio = std::max(max_volume_ratio, o.max_volume_ratio);
    }
};

// The report of `cells` cells from the tallies of their cells and faces.
QualityReport make_report(Id cells, const CellStats& per_cell, const FaceStats& per_face);

// The per-cell part of the first pass: aspect ratio, volume, scaled Jacobian, validity.
void add_cell(CellStats& acc, Id cell, const std::array<FaceGeometry, 6>& faces,
              const CellGeometry& g, const std::array<Vec3, 8>& p);

// checkMesh's non-orthogonality error: the face's cosine (face_orthogonality) at most SMALL.
bool at_90_deg_or_more(double ortho);

// The second pass's measures of an internal face: p, g as its owner sees it.
void add_internal_face(FaceStats& acc, const std::array<Vec3, 4>& p, const FaceGeometry& g,
                       const Vec3& own_cc, const Vec3& nei_cc, double own_volume,
                       double nei_volume);

}  // namespace hexmesh::detail

// Quality of a hex mesh as a finite-volume solver sees it: validity, scaled Jacobian,
// OpenFOAM's checkMesh face and cell metrics, gathered in a QualityReport.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "hexmesh/core/hex_mesh.h"
#include "hexmesh/core/histogram.h"

namespace hexmesh {

// A cell and its scaled Jacobian, for the list of a grid's worst cells.
struct RankedCell {
    Id cell = -1;
    double scaled_jacobian = 0;
    Vec3 centre = Vec3::Zero();  // OpenFOAM's
};
inline constexpr std::size_t worst_cells_listed = 20;

// checkMesh fails a mesh with a face of skewness over this (primitiveMesh::skewThreshold_).
inline constexpr double max_solver_skewness = 4;
// checkMesh fails a mesh with a cell of aspect ratio over this (primitiveMesh::aspectThreshold_),
// though solvers run on such cells: a boundary layer resolved to the wall has them.
inline constexpr double checkmesh_max_aspect_ratio = 1000;

// The bins the report counts its cells and faces in.
inline Histogram scaled_jacobian_bins() {
    return Histogram(-1, 1, 20);
}  // 0.1 wide
inline Histogram non_orthogonality_bins() {
    return Histogram(0, 180, 18);
}  // 10 degrees wide

struct QualityReport {
    Id cells = 0;
    Id inverted_corner_tets = 0;  // corner tets with det <= 0, by exact orientation predicate
    Id inverted_cells = 0;        // cells with at least one such corner tet
    // Verdict values: a cell with a zero-length edge scores +1e30 (and is also counted
    // inverted, since it has a flat corner tet); the mean takes each cell's value clamped to
    // [-1, 1], so that such a cell does not swamp it.
    double min_scaled_jacobian = 0;
    double mean_scaled_jacobian = 0;
    // The cell of min_scaled_jacobian (the lowest id among equals; -1 without cells) and its
    // centre (OpenFOAM's).
    Id worst_cell = -1;
    Vec3 worst_cell_centre = Vec3::Zero();
    double max_skewness = 0;               // OpenFOAM checkMesh definition, all faces
    double max_non_orthogonality_deg = 0;  // OpenFOAM checkMesh definition, internal faces
    double max_aspect_ratio = 0;           // OpenFOAM checkMesh definition (cellClosedness)
    double max_volume_ratio = 0;           // max over internal faces of V_big / V_small
    double min_volume = 0;                 // OpenFOAM's cell volume (pyramid decomposition)
    // What a finite-volume solver refuses although every corner tet is positive (a cell
    // turned inside out at its centre, a face warped past its cell's centre), counted as
    // OpenFOAM's checkMesh counts it: face pyramids (each face against the centre of each of
    // its cells) of negative volume, internal faces whose non-orthogonality is 90 degrees or
    // more, cells of zero or negative volume, faces (internal or boundary) of skewness over 4.
    Id negative_pyramids = 0;
    Id faces_over_90_deg = 0;
    Id nonpositive_volumes = 0;
    Id highly_skewed_faces = 0;
    // Cells of aspect ratio over checkmesh_max_aspect_ratio: counted (checkMesh fails the mesh
    // for them), not refused (solvers run on them).
    Id high_aspect_ratio_cells = 0;
    // The worst_cells_listed cells of lowest scaled Jacobian, ascending (the lower id first
    // among equals); the first is worst_cell.
    std::vector<RankedCell> worst_cells;
    // Every cell's scaled Jacobian (a cell with a zero-length edge, 1e30, counts above), and
    // every internal face's non-orthogonality in degrees (the faces_over_90_deg in the bins
    // from 90 up: a face checkMesh counts there is never put under 90).
    Histogram scaled_jacobian_histogram = scaled_jacobian_bins();
    Histogram non_orthogonality_histogram = non_orthogonality_bins();
    Id internal_faces = 0;
    // No inverted corner tet and none of the refused checks above: a grid that checkMesh does
    // not fail for its cells' and faces' shapes, but for cells over its aspect-ratio limit
    // (high_aspect_ratio_cells, which solvers run on); it may still warn about
    // non-orthogonality over 70 degrees.
    bool solver_valid() const { return refused_count() == 0 && inverted_corner_tets == 0; }
    // How many cells and faces fail the checks above (a cell or face may count twice).
    Id refused_count() const {
        return inverted_cells + negative_pyramids + faces_over_90_deg + nonpositive_volumes +
               highly_skewed_faces;
    }
};

// How far one hex (VTK order) is from what QualityReport::solver_valid refuses of it alone (not
// the skewness of its faces, which needs the cells across them): the smallest of its 8 corner
// scaled Jacobians and, for each face, the distance of the cell's OpenFOAM centre inside the
// face's plane (its area vector against face centre - cell centre) over the cell's mean edge
// length. Positive for every cell of a mesh exactly when no corner tet is
// flat or inverted and no face pyramid has a negative volume, and then no internal face is at
// 90 degrees or more (the two centres lie on either side of its plane) and no cell's volume is
// <= 0 (a sum of positive pyramids).
double solver_margin(const std::array<Vec3, 8>& p);

// The 14 terms whose smallest is solver_margin: the 8 corner scaled Jacobians (hex_corner_tets
// order), then the 6 faces' (BlockFace order of hex_face_geometries). Each is smooth where the
// smallest is not: an ascent that raises the margin raises each term near it.
std::array<double, 14> solver_margins(const std::array<Vec3, 8>& p);

// OpenFOAM's centre of one hex (VTK order): the volume-weighted centre of its face pyramids.
Vec3 hex_centre(const std::array<Vec3, 8>& p);

// checkMesh's skewness of local face f (hex_faces order) of the hex p (VTK order) of centre
// `centre` (hex_centre) against the centre of the cell across it, or as a boundary face when
// `across` is null (the same from either side). Over max_solver_skewness fails the mesh.
double hex_face_skewness(const std::array<Vec3, 8>& p, int f, const Vec3& centre,
                         const Vec3* across);

// For each face 6 c + f of the mesh (local face f of cell c, hex_faces order), the cell across
// it, or -1 on the boundary. Faces are matched by their node ids, as in measure_quality.
std::vector<Id> face_neighbours(const HexMesh& mesh);

// The cells that fail a check of QualityReport::solver_valid (an inverted corner tet, a face
// pyramid of negative volume, volume <= 0; a face at 90 degrees or more or of skewness over 4:
// its cells), ascending.
std::vector<Id> find_refused_cells(const HexMesh& mesh);

// Every metric above over all cells. Faces are matched between cells by their node ids; the
// owner of an internal face is the lower cell id. A face shared by more than two cells
// throws std::invalid_argument naming the cells.
QualityReport measure_quality(const HexMesh& mesh);

}  // namespace hexmesh

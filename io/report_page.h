// report.html: one self-contained page (no network, no scripts) with a grid's pictures,
// histograms of its quality, its worst cells, the settings used, time per phase and memory.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hexmesh/core/histogram.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/grid_pictures.h"

namespace hexmesh {

struct ReportHistogram {
    std::string name;     // key in the page's data ("scaled_jacobian", ...)
    std::string title;    // heading
    std::string x_label;  // what the bins count
    Histogram bins;
    std::string note;  // a line under it (what "within target" is, ...)
};

// One of the worst cells: its value, where it is (a block grid's block and (i, j, k), or the
// cell id) and its centre, marked with its rank on the pictures.
struct ReportCell {
    double value = 0;
    std::string where;
    Vec3 centre = Vec3::Zero();
    bool on_wall = false;  // marked on the wall views only when on the wall
};

struct ReportPage {
    std::string title;                           // the command and its input
    std::string summary;                         // one line: cells, valid or not, min of the value
    std::string value_name = "scaled Jacobian";  // what colours the pictures
    double value_lo = 0, value_hi = 1;           // its colour scale
    std::vector<Picture> pictures;
    std::vector<ReportHistogram> histograms;
    std::vector<ReportCell> worst;
    std::string quality_table;  // the terminal's table
    std::string quality_json;   // also embedded as data
    std::string settings_json;  // the settings used, automatic choices included
    std::vector<std::pair<std::string, double>> phase_seconds;
    double peak_memory_bytes = 0;
};

// The page's HTML. Its data (histograms' bins and counts, the worst cells, quality.json)
// is also embedded as JSON in <script type="application/json" id="hexmesh-report">, for
// tools; the page itself runs no script.
std::string report_page_html(const ReportPage& page);

// Two pages side by side (e.g. two levels of a family, two optimizations of a mesh), section
// by section; the data of each as {"a": ..., "b": ...}.
std::string compare_page_html(const ReportPage& a, const ReportPage& b);

// The page of a block grid's report: histograms of scaled Jacobian and non-orthogonality,
// and with a wall, of first-layer height over its target and of growth ratio; the worst
// cells with their blocks; `pictures` drawn by GridPictures with the scaled Jacobian on
// [-1, 1] (or none).
ReportPage grid_report_page(const std::string& title, const GridReport& report,
                            std::vector<Picture> pictures, const std::string& settings_json);

// The pictures of a block grid whose whole is at hand: wall from four sides and cuts, cells
// coloured by scaled Jacobian. Faces with patch "wall" are the wall; without any, the
// grid's boundary faces.
std::vector<Picture> draw_grid(const BlockGrid& grid);

// The page of an unstructured hex mesh (`quality` its measure_quality): histograms of scaled
// Jacobian and non-orthogonality, the worst cells by id, pictures of its boundary faces and
// cuts coloured by scaled Jacobian.
ReportPage hex_mesh_report_page(const std::string& title, const HexMesh& mesh,
                                const QualityReport& quality);

// The page of a tet mesh: histograms of each tet's smallest dihedral angle and of its radius
// ratio, the tets of smallest dihedral angle, pictures of its boundary faces and cuts
// coloured by that angle (over [0, 70.5], a regular tet's).
ReportPage tet_mesh_report_page(const std::string& title, const TetMesh& mesh,
                                const TetQualityReport& quality);

// Writes `html` as `file`, first in a staging folder beside it, then renamed into place;
// returns its path.
std::string write_page(const std::filesystem::path& file, const std::string& html);

// Writes the page as NAME.report.html beside the mesh file NAME.EXT (the file itself first
// in a staging folder, then renamed into place); returns its path.
std::string write_report_beside(const std::string& mesh_file, const ReportPage& page);

// GridPictures framed for `grid` (its wall's box and its box), to add a grid block by block
// (e.g. the refined blocks of `grid` as they are made).
GridPictures grid_pictures_for(const BlockGrid& grid);

}  // namespace hexmesh

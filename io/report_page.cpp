#include "io/report_page.h"

#include <fmt/format.h>
#include <vtkBase64Utilities.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numeric>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/tet_quality.h"
#include "io/markup.h"
#include "io/staged_output.h"

namespace hexmesh {
namespace {

std::string base64(const std::string& bytes) {
    std::string out(4 * ((bytes.size() + 2) / 3) + 4, '\0');
    const unsigned long n =
        vtkBase64Utilities::Encode(reinterpret_cast<const unsigned char*>(bytes.data()),
                                   bytes.size(), reinterpret_cast<unsigned char*>(out.data()),
                                   0);  // 1 would append "====" to a length a multiple of 3
    out.resize(n);
    return out;
}

// A bin's bounds, short.
std::string bin_label(double v) {
    return fmt::format("{:.3g}", v);
}

// A bar chart of the histogram as inline SVG: bar heights on a logarithmic scale (so that
// the few bad cells of a good grid show), each bar's count written over it.
std::string histogram_svg(const ReportHistogram& h) {
    const Histogram& b = h.bins;
    const int bins = int(b.counts.size());
    const double left = 40, bottom = 30, top = 18, width = 560, height = 190;
    const double bar = (width - left - 10) / std::max(bins, 1);
    Id most = 1;
    for (Id c : b.counts) most = std::max(most, c);
    const double scale = (height - top - bottom) / std::log10(1.0 + double(most));
    std::string svg = fmt::format(
        "<svg class=\"histogram\" data-name=\"{}\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} "
        "{}\" "
        "xmlns=\"http://www.w3.org/2000/svg\">\n",
        h.name, width, height, width, height);
    svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#444\"/>\n", left,
                       height - bottom, width - 10, height - bottom);
    for (int i = 0; i < bins; ++i) {
        const Id c = b.counts[i];
        const double x = left + i * bar;
        const double hgt = c > 0 ? std::max(1.0, scale * std::log10(1.0 + double(c))) : 0;
        const double lo = b.lo + i * b.bin_width(), hi = lo + b.bin_width();
        svg += fmt::format(
            "<rect class=\"bar\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
            "fill=\"#4a7fb0\" data-count=\"{}\"><title>[{}, {}): {}</title></rect>\n",
            x + 1, height - bottom - hgt, bar - 2, hgt, c, bin_label(lo), bin_label(hi), c);
        if (c > 0)
            svg += fmt::format(
                "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"9\" "
                "text-anchor=\"middle\">{}</text>\n",
                x + 0.5 * bar, height - bottom - hgt - 3, c);
        if (i % 2 == 0 || bins <= 10)
            svg += fmt::format(
                "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"10\" "
                "text-anchor=\"middle\">{}</text>\n",
                x, height - bottom + 13, bin_label(lo));
    }
    svg += fmt::format(
        "<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"10\" text-anchor=\"middle\">{}</text>\n",
        left + bins * bar, height - bottom + 13, bin_label(b.hi));
    svg +=
        fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"11\" text-anchor=\"middle\">{}</text>\n",
                    left + 0.5 * (width - left), height - 3, escape_markup(h.x_label));
    svg += "</svg>\n";
    return svg;
}

// The colour scale as an SVG bar with ticks.
std::string legend_svg(const ReportPage& page) {
    std::string svg = "<svg width=\"420\" height=\"46\" xmlns=\"http://www.w3.org/2000/svg\">\n";
    const int steps = 40;
    for (int s = 0; s < steps; ++s) {
        const double v = page.value_lo + (page.value_hi - page.value_lo) * (s + 0.5) / steps;
        const auto c = value_colour(v, page.value_lo, page.value_hi);
        svg += fmt::format(
            "<rect x=\"{}\" y=\"4\" width=\"{}\" height=\"16\" fill=\"rgb({},{},{})\"/>\n",
            40 + s * 8, 8, c[0], c[1], c[2]);
    }
    const auto under = value_colour(page.value_lo - 1, page.value_lo, page.value_hi);
    svg +=
        fmt::format("<rect x=\"4\" y=\"4\" width=\"28\" height=\"16\" fill=\"rgb({},{},{})\"/>\n",
                    under[0], under[1], under[2]);
    svg += fmt::format(
        "<text x=\"18\" y=\"34\" font-size=\"10\" text-anchor=\"middle\">&lt; {}</text>\n",
        bin_label(page.value_lo));
    for (int t = 0; t <= 4; ++t)
        svg += fmt::format(
            "<text x=\"{}\" y=\"34\" font-size=\"10\" text-anchor=\"middle\">{}</text>\n",
            40 + t * 80, bin_label(page.value_lo + (page.value_hi - page.value_lo) * t / 4));
    svg +=
        fmt::format("<text x=\"200\" y=\"45\" font-size=\"10\" text-anchor=\"middle\">{}</text>\n",
                    escape_markup(page.value_name));
    return svg + "</svg>\n";
}

// A picture with the worst cells marked by their rank: on a wall view the cells on the wall,
// on a cut the cells whose centre is within a few pixels of the plane.
std::string picture_svg(const Picture& p, const std::vector<ReportCell>& worst, bool wall_view) {
    const View& v = p.view;
    std::string svg = fmt::format(
        "<svg class=\"picture\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
        "xmlns=\"http://www.w3.org/2000/svg\">\n<image width=\"{0}\" height=\"{1}\" "
        "href=\"data:image/png;base64,{2}\"/>\n",
        v.width, v.height, base64(p.png));
    for (std::size_t r = 0; r < worst.size(); ++r) {
        const Vec3 at = v.pixel(worst[r].centre);
        if (at.x() < 0 || at.y() < 0 || at.x() > v.width || at.y() > v.height) continue;
        if (wall_view ? !worst[r].on_wall : std::abs(at.z()) * v.pixels_per_unit > 6) continue;
        svg += fmt::format(
            "<g class=\"mark\"><circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"7\" fill=\"none\" "
            "stroke=\"black\" stroke-width=\"2\"/><text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"11\" "
            "font-weight=\"bold\">{}</text></g>\n",
            at.x(), at.y(), at.x() + 8, at.y() - 8, r + 1);
    }
    return svg + "</svg>\n";
}

nlohmann::ordered_json histogram_json(const ReportHistogram& h) {
    nlohmann::ordered_json j;
    j["name"] = h.name;
    j["lo"] = h.bins.lo;
    j["hi"] = h.bins.hi;
    j["counts"] = h.bins.counts;
    j["below"] = h.bins.below;
    j["above"] = h.bins.above;
    j["total"] = h.bins.total();
    return j;
}

const char* style = R"(body{font-family:sans-serif;margin:20px;color:#222;max-width:1400px}
h1{font-size:22px}h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ccc}
figure{display:inline-block;margin:6px;vertical-align:top}figcaption{font-size:12px;text-align:center}
table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}
td.side{vertical-align:top;text-align:left;border:none;padding:0 12px}
th{background:#eee}td.l{text-align:left}pre{background:#f6f6f6;padding:8px;font-size:12px;overflow:auto}
.bad{color:#b00;font-weight:bold}.good{color:#070;font-weight:bold}
)";

// The page's sections, from its heading to its settings.
std::string page_body(const ReportPage& page) {
    std::string html;
    html += fmt::format("<h1>{}</h1>\n<p class=\"summary\">{}</p>\n", escape_markup(page.title),
                        page.summary);

    html += "<h2>Pictures</h2>\n<p>Cells coloured by " + escape_markup(page.value_name) +
            "; the numbers mark the worst cells (table below): on the wall views those on the "
            "wall, on the cuts those the plane crosses.</p>\n" +
            legend_svg(page) + "<div>\n";
    for (const Picture& p : page.pictures)
        html += "<figure>" + picture_svg(p, page.worst, !p.cut) + "<figcaption>" +
                escape_markup(p.title) + "</figcaption></figure>\n";
    html += "</div>\n";

    html +=
        "<h2>Histograms</h2>\n<p>Bar heights on a logarithmic scale; the count over each "
        "bar.</p>\n";
    for (const ReportHistogram& h : page.histograms) {
        html += "<figure>" + histogram_svg(h) + "<figcaption><b>" + escape_markup(h.title) + "</b>";
        if (h.bins.below || h.bins.above)
            html += fmt::format(" &mdash; under {}: {}, from {} up: {}", bin_label(h.bins.lo),
                                h.bins.below, bin_label(h.bins.hi), h.bins.above);
        if (!h.note.empty()) html += "<br>" + escape_markup(h.note);
        html += "</figcaption></figure>\n";
    }

    html += fmt::format(
        "<h2>The {} worst cells</h2>\n<table class=\"worst\">\n<tr><th>rank</th><th>{}</th>"
        "<th>where</th><th>centre</th></tr>\n",
        page.worst.size(), escape_markup(page.value_name));
    for (std::size_t r = 0; r < page.worst.size(); ++r) {
        const ReportCell& c = page.worst[r];
        html += fmt::format(
            "<tr><td>{}</td><td>{:.4g}</td><td class=\"l\">{}</td><td>({:.5g}, {:.5g}, "
            "{:.5g})</td></tr>\n",
            r + 1, c.value, escape_markup(c.where), c.centre.x(), c.centre.y(), c.centre.z());
    }
    html += "</table>\n";

    html += "<h2>Quality</h2>\n<pre>" + escape_markup(page.quality_table) + "</pre>\n";
    html += "<h2>Time and memory</h2>\n";
    if (!page.phase_seconds.empty()) {
        html += "<table class=\"phases\">\n<tr><th>phase</th><th>seconds</th></tr>\n";
        double total = 0;
        for (const auto& [phase, seconds] : page.phase_seconds) {
            html += fmt::format("<tr><td class=\"l\">{}</td><td>{:.2f}</td></tr>\n",
                                escape_markup(phase), seconds);
            total += seconds;
        }
        html += fmt::format("<tr><th>total</th><th>{:.2f}</th></tr>\n</table>\n", total);
    }
    html += fmt::format("<p>Peak memory: {:.0f} MB</p>\n", page.peak_memory_bytes / 1e6);
    if (!page.settings_json.empty())
        html +=
            "<h2>Settings</h2>\n<p>Every setting the run used, its automatic choices included "
            "(grid.case.json).</p>\n<pre class=\"settings\">" +
            escape_markup(page.settings_json) + "</pre>\n";

    return html;
}

// The page's numbers for tools: histograms, worst cells, pictures drawn, quality.json.
nlohmann::ordered_json page_data(const ReportPage& page) {
    nlohmann::ordered_json data;
    data["histograms"] = nlohmann::ordered_json::array();
    for (const ReportHistogram& h : page.histograms)
        data["histograms"].push_back(histogram_json(h));
    data["worst"] = nlohmann::ordered_json::array();
    for (const ReportCell& c : page.worst)
        data["worst"].push_back({{"value", c.value},
                                 {"where", c.where},
                                 {"centre", {c.centre.x(), c.centre.y(), c.centre.z()}}});
    data["pictures"] = page.pictures.size();
    if (!page.quality_json.empty())
        data["quality"] = nlohmann::ordered_json::parse(page.quality_json);
    return data;
}

// A document around `body`, with `data` embedded as JSON.
std::string html_document(const std::string& title, const std::string& body,
                          const nlohmann::ordered_json& data) {
    std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
    html += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n",
                        escape_markup(title), style);
    html += body;
    std::string json = data.dump();
    for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 2))
        json.replace(at, 2, "<\\/");
    html += "<script type=\"application/json\" id=\"hexmesh-report\">" + json + "</script>\n";
    return html + "</body>\n</html>\n";
}

}  // namespace

std::string report_page_html(const ReportPage& page) {
    return html_document(page.title, page_body(page), page_data(page));
}

std::string compare_page_html(const ReportPage& a, const ReportPage& b) {
    const std::string title = "hexmesh compare: " + a.title + " | " + b.title;
    std::string body = "<table class=\"compare\"><tr>\n";
    for (const ReportPage* page : {&a, &b})
        body += "<td class=\"side\">\n" + page_body(*page) + "</td>\n";
    body += "</tr></table>\n";
    nlohmann::ordered_json data;
    data["a"] = page_data(a);
    data["b"] = page_data(b);
    return html_document(title, body, data);
}

ReportPage grid_report_page(const std::string& title, const GridReport& report,
                            std::vector<Picture> pictures, const std::string& settings_json) {
    const QualityReport& q = report.quality;
    ReportPage page;
    page.title = title;
    page.summary = fmt::format(
        "{} cells: <span class=\"{}\">{}</span>; min scaled Jacobian {:.4g}, mean {:.4g}.", q.cells,
        q.solver_valid() ? "good" : "bad",
        q.solver_valid()
            ? "valid"
            : fmt::format("not valid for a solver ({} inverted cells, {} face pyramids "
                          "of negative volume, {} faces at 90 degrees or more)",
                          q.inverted_cells, q.negative_pyramids, q.faces_over_90_deg),
        q.min_scaled_jacobian, q.mean_scaled_jacobian);
    if (const std::string missed = body_missed(report); !missed.empty())
        page.summary += fmt::format(" <span class=\"bad\">Not the body's grid: {}.</span>", missed);
    page.value_lo = 0;  // under 0 (inverted) gets its own colour
    page.value_hi = 1;
    page.pictures = std::move(pictures);
    page.histograms.push_back(
        {"scaled_jacobian", "Scaled Jacobian of the cells", "scaled Jacobian",
         q.scaled_jacobian_histogram,
         fmt::format("{} cells; 1 is a cube, 0 or less a cell folded at a corner", q.cells)});
    page.histograms.push_back(
        {"non_orthogonality", "Non-orthogonality of the internal faces",
         "degrees (OpenFOAM's definition)", q.non_orthogonality_histogram,
         fmt::format("{} internal faces; solvers refuse 90 degrees or more ({} here)",
                     q.internal_faces, q.faces_over_90_deg)});
    if (report.wall) {
        const WallQuality& w = *report.wall;
        if (w.first_layer_target > 0)
            page.histograms.push_back(
                {"first_layer", "First-layer height over its target", "height / target",
                 w.first_layer_histogram,
                 fmt::format(
                     "{} wall cells, target {:.4g}; {:.1f} % within 10 % (the bins 0.9 and 1.0)",
                     w.wall_cells, w.first_layer_target, 100 * w.first_layer_within_10_percent)});
        if (w.growth_ratios > 0)
            page.histograms.push_back(
                {"growth_ratio",
                 w.growth_ratio_target > 0 ? "Growth ratio over its target"
                                           : "Growth ratio along the wall-normal lines",
                 w.growth_ratio_target > 0 ? "ratio / target" : "ratio", w.growth_ratio_histogram,
                 w.growth_ratio_target > 0
                     ? fmt::format(
                           "{} ratios in the boundary layer, target {:.4g}; {:.1f} % within 5 %",
                           w.growth_ratios, w.growth_ratio_target,
                           100 * w.growth_ratio_within_5_percent)
                     : fmt::format("{} ratios", w.growth_ratios)});
    }
    for (std::size_t r = 0; r < q.worst_cells.size(); ++r) {
        const RankedCell& c = q.worst_cells[r];
        ReportCell cell{c.scaled_jacobian, fmt::format("cell {}", c.cell), c.centre, false};
        if (r < report.worst_places.size() && !report.worst_places[r].block.empty()) {
            const CellPlace& p = report.worst_places[r];
            cell.where = fmt::format("block {} ({}, {}, {}){}", p.block, p.i, p.j, p.k,
                                     p.on_wall ? ", on the wall" : "");
            cell.on_wall = p.on_wall;
        }
        page.worst.push_back(cell);
    }
    page.quality_table = format_quality_table(report);
    page.quality_json = quality_json(report);
    page.settings_json = settings_json;
    page.phase_seconds = report.phase_seconds;
    return page;
}

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

std::string write_page(const std::filesystem::path& file, const std::string& html) {
    StagedOutput out(file.parent_path().empty() ? "." : file.parent_path().string(),
                     StagedOutput::Scope::named_entries);
    out.write_text(file.filename().string(), html);
    return out.commit().at(0);
}

std::string write_report_beside(const std::string& mesh_file, const ReportPage& page) {
    const std::filesystem::path mesh(mesh_file);
    return write_page(mesh.parent_path() / (mesh.stem().string() + ".report.html"),
                      report_page_html(page));
}

GridPictures grid_pictures_for(const BlockGrid& grid) {
    std::vector<Vec3> wall;  // the nodes of the faces whose patch is "wall"
    for (const Block& block : grid.blocks)
        for (int f = 0; f < 6; ++f) {
            if (block.face_patch[f] != "wall") continue;
            const Dims n = block.nodes;
            const int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::array<int, 3> at;
            at[axis] = f % 2 ? n[axis] - 1 : 0;
            for (at[v] = 0; at[v] < n[v]; ++at[v])
                for (at[u] = 0; at[u] < n[u]; ++at[u])
                    wall.push_back(grid.points[block.node_ids[n.flat(at[0], at[1], at[2])]]);
        }
    const Box3 domain = bounds_of(grid.points);
    return GridPictures(wall.empty() ? domain : bounds_of(wall), domain, 0, 1);
}

std::vector<Picture> draw_grid(const BlockGrid& grid) {
    GridPictures pictures = grid_pictures_for(grid);
    bool has_wall = false;
    for (const Block& block : grid.blocks)
        for (const std::string& patch : block.face_patch) has_wall = has_wall || patch == "wall";
    std::vector<double> values;
    for (const Block& block : grid.blocks) {
        values.resize(std::size_t(block.cells().count()));
        scaled_jacobians(grid, block, values.data());
        pictures.add_block(grid, block, values.data(), !has_wall);
    }
    return pictures.pictures();
}

}  // namespace hexmesh

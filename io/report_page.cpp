// A report page as one self-contained HTML document: its sections (pictures, histograms,
// worst cells, quality, time and memory, settings), its data embedded as JSON, two pages side
// by side, and the writing of a page into place.
#include "io/report_page.h"

#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/markup.h"
#include "io/report_svg.h"
#include "io/staged_output.h"

namespace hexmesh {
namespace {

// A histogram's bins and counts as the page's data gives them.
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

// The page's style sheet.
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

}  // namespace hexmesh

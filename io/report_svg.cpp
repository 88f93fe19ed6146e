// The pictures of a report page as inline SVG: bar charts of the histograms, the colour
// scale, each picture (a PNG in base64) with the worst cells marked by their rank.
#include "io/report_svg.h"

#include <fmt/format.h>
#include <vtkBase64Utilities.h>

#include <algorithm>
#include <cmath>

#include "io/markup.h"

namespace hexmesh {
namespace {

// `bytes` in base64 (a PNG inlined in an <image>).
std::string base64(const std::string& bytes) {
    std::string out(4 * ((bytes.size() + 2) / 3) + 4, '\0');
    const unsigned long n =
        vtkBase64Utilities::Encode(reinterpret_cast<const unsigned char*>(bytes.data()),
                                   bytes.size(), reinterpret_cast<unsigned char*>(out.data()),
                                   0);  // 1 would append "====" to a length a multiple of 3
    out.resize(n);
    return out;
}

}  // namespace

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

}  // namespace hexmesh

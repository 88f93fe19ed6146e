// Private to io/: the pictures of a report page (io/report_page.h) as inline SVG, the quality
// histograms as bar charts, the colour scale, the grid's pictures with the worst cells marked.
#pragma once

#include <string>
#include <vector>

#include "io/report_page.h"

namespace hexmesh {

// A bin's bounds, short.
std::string bin_label(double v);

// A bar chart of the histogram as inline SVG: bar heights on a logarithmic scale (so that
// the few bad cells of a good grid show), each bar's count written over it.
std::string histogram_svg(const ReportHistogram& h);

// The colour scale as an SVG bar with ticks.
std::string legend_svg(const ReportPage& page);

// A picture with the worst cells marked by their rank: on a wall view the cells on the wall,
// on a cut the cells whose centre is within a few pixels of the plane.
std::string picture_svg(const Picture& p, const std::vector<ReportCell>& worst, bool wall_view);

}  // namespace hexmesh

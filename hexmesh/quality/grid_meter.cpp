// GridMeter: a block grid measured into a GridReport, block by block.
#include "hexmesh/quality/grid_meter.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "hexmesh/core/bytes.h"
#include "hexmesh/core/reference_hex.h"

namespace hexmesh {
namespace {

// Sum of the lengths of the block's cell edges whose two ends are wall (slip) nodes, and
// their count; an edge counts once per cell it bounds. Deterministic: each block split alike.
std::pair<double, Id> wall_edge_lengths(const BlockGrid& grid, const Block& block) {
    using Sum = std::pair<double, Id>;
    const Dims d = block.cells();
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<int>(0, d.nk, 1), Sum{0, 0},
        [&](const tbb::blocked_range<int>& r, Sum acc) {
            for (int k = r.begin(); k != r.end(); ++k)
                for (int j = 0; j < d.nj; ++j)
                    for (int i = 0; i < d.ni; ++i) {
                        const std::array<Id, 8> nodes = cell_nodes(block, i, j, k);
                        for (const auto& e : hex_edges) {
                            const Id a = nodes[e[0]], b = nodes[e[1]];
                            if (grid.kinds[a] != VertexKind::slip ||
                                grid.kinds[b] != VertexKind::slip)
                                continue;
                            acc.first += (grid.points[a] - grid.points[b]).norm();
                            ++acc.second;
                        }
                    }
            return acc;
        },
        [](Sum x, const Sum& y) {
            return Sum{x.first + y.first, x.second + y.second};
        });
}

// max |u| over the block's slip nodes.
double max_slip_value(const BlockGrid& grid, const Block& block, const ImplicitFunction& body) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, block.node_ids.size(), 4096), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double worst) {
            for (size_t m = r.begin(); m != r.end(); ++m) {
                const Id v = block.node_ids[m];
                if (grid.kinds[v] == VertexKind::slip)
                    worst = std::max(worst, std::abs(body.value(grid.points[v])));
            }
            return worst;
        },
        [](double a, double b) { return std::max(a, b); });
}

}  // namespace

GridMeter::GridMeter(const ImplicitFunction& body, const WallLayers& law,
                     const TriangleSurface* surface)
    : body_(body), surface_(surface), wall_(body, law) {}

void GridMeter::add(const BlockGrid& grid, const Block& block, const std::vector<Id>* ids,
                    const CellNumbering& numbering) {
    quality_.add(grid, block, ids, numbering);
    Added a;
    a.name = block.name;
    a.cells = block.cells();
    a.first_cell = numbering.first >= 0 ? numbering.first : cells_;
    a.offset = numbering.offset;
    a.whole = numbering.whole.count() > 0 ? numbering.whole : a.cells;
    cells_ += block.cells().count();
    for (int f = 0; f < 6; ++f) a.wall[f] = block.face_patch[f] == "wall";
    const bool walled = std::find(a.wall.begin(), a.wall.end(), true) != a.wall.end();
    added_.push_back(std::move(a));
    if (walled) {
        has_wall_ = true;
        wall_.add(grid, block,
                  {numbering.offset[0] > 0, numbering.offset[1] > 0, numbering.offset[2] > 0});
        if (surface_) append_wall_triangles(grid, block, wall_triangles_);
    }
    const auto [length, edges] = wall_edge_lengths(grid, block);
    wall_edge_length_ += length;
    wall_edges_ += edges;
    max_slip_value_ = std::max(max_slip_value_, max_slip_value(grid, block, body_));
}

std::optional<CellPlace> GridMeter::place(Id cell) const {
    for (const Added& a : added_) {
        const Id c = cell - a.first_cell;
        if (c < 0 || c >= a.whole.count()) continue;
        const std::array<int, 3> at = {int(c % a.whole.ni), int(c / a.whole.ni % a.whole.nj),
                                       int(c / (Id(a.whole.ni) * a.whole.nj))};
        std::array<int, 3> in;  // in the part added
        for (int d = 0; d < 3; ++d) in[d] = at[d] - a.offset[d];
        if (in[0] < 0 || in[1] < 0 || in[2] < 0 || in[0] >= a.cells.ni || in[1] >= a.cells.nj ||
            in[2] >= a.cells.nk)
            continue;
        CellPlace w{a.name, at[0], at[1], at[2], false};
        for (int f = 0; f < 6; ++f)
            w.on_wall = w.on_wall || (a.wall[f] && on_block_face(a.cells, in, f));
        return w;
    }
    return std::nullopt;
}

std::string GridMeter::pack() const {
    ByteWriter out;
    out.put(quality_.pack());
    out.put(wall_.pack());
    out.put(has_wall_), out.put(cells_);
    out.put(wall_triangles_.points), out.put(wall_triangles_.triangles);
    out.put(wall_edge_length_), out.put(wall_edges_), out.put(max_slip_value_);
    out.put(added_.size());
    for (const Added& a : added_)
        out.put(a.name), out.put(a.cells), out.put(a.wall), out.put(a.first_cell),
            out.put(a.offset), out.put(a.whole);
    return out.bytes();
}

void GridMeter::merge(const std::string& packed) {
    ByteReader in(packed);
    quality_.merge(in.next<std::string>());
    wall_.merge(in.next<std::string>());
    has_wall_ = in.next<bool>() || has_wall_;
    cells_ += in.next<Id>();
    const int offset = int(wall_triangles_.points.size());
    const std::vector<Vec3> points = in.next<std::vector<Vec3>>();
    std::vector<std::array<int, 3>> triangles = in.next<std::vector<std::array<int, 3>>>();
    wall_triangles_.points.insert(wall_triangles_.points.end(), points.begin(), points.end());
    for (std::array<int, 3>& t : triangles) {
        for (int& v : t) v += offset;
        wall_triangles_.triangles.push_back(t);
    }
    wall_edge_length_ += in.next<double>();
    wall_edges_ += in.next<Id>();
    max_slip_value_ = std::max(max_slip_value_, in.next<double>());
    const size_t blocks = in.next<size_t>();
    for (size_t b = 0; b < blocks; ++b) {
        Added a;
        in.get(a.name), in.get(a.cells), in.get(a.wall), in.get(a.first_cell), in.get(a.offset),
            in.get(a.whole);
        added_.push_back(std::move(a));
    }
}

GridReport GridMeter::report() const {
    GridReport report;
    report.quality = quality_.report();
    report.worst_cell = place(report.quality.worst_cell);
    for (const RankedCell& r : report.quality.worst_cells)
        report.worst_places.push_back(place(r.cell).value_or(CellPlace{}));
    if (has_wall_) {
        report.wall = wall_.result();
        if (surface_) {
            const HausdorffDistance d = hausdorff_to_surface(wall_triangles_, *surface_);
            report.wall->hausdorff = d.hausdorff;
            report.wall->grid_to_surface = d.grid_to_surface;
            report.wall->surface_to_grid = d.surface_to_grid;
            report.wall->surface_in_cells_max = d.surface_in_cells_max;
            report.wall->surface_in_cells_p99 = d.surface_in_cells_p99;
            report.wall->surface_in_cells_at = d.surface_in_cells_at;
            report.wall->surface_in_cells_distance = d.surface_in_cells_distance;
        }
    }
    // h: mean length of the hex edges whose two ends lie on the wall (counted once per cell).
    if (wall_edges_ == 0) return report;
    const double h = wall_edge_length_ / wall_edges_;
    report.length_scale = h;
    report.max_surface_distance = max_slip_value_ / h;
    return report;
}

GridReport measure_grid(const BlockGrid& grid, const ImplicitFunction& body, const WallLayers& law,
                        const TriangleSurface* surface) {
    GridMeter meter(body, law, surface);
    for (const Block& block : grid.blocks) meter.add(grid, block);
    return meter.report();
}

}  // namespace hexmesh

#include "io/grid_pictures.h"

#include <fmt/format.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "hexmesh/core/bytes.h"
#include "hexmesh/core/reference_hex.h"

namespace hexmesh {

View View::framing(const Box3& box, const Vec3& towards_viewer, const Vec3& up, int width,
                   int height) {
    View v;
    v.width = width;
    v.height = height;
    v.centre = box.center();
    v.towards_viewer = towards_viewer.normalized();
    v.right = up.cross(v.towards_viewer).normalized();
    v.up = v.towards_viewer.cross(v.right);
    // The box's corners projected: the extent along right and up.
    double half_w = 0, half_h = 0;
    for (int c = 0; c < 8; ++c) {
        const Vec3 p(c & 1 ? box.hi.x() : box.lo.x(), c & 2 ? box.hi.y() : box.lo.y(),
                     c & 4 ? box.hi.z() : box.lo.z());
        half_w = std::max(half_w, std::abs((p - v.centre).dot(v.right)));
        half_h = std::max(half_h, std::abs((p - v.centre).dot(v.up)));
    }
    const double margin = 0.92;  // of the picture the box fills
    v.pixels_per_unit = margin * std::min(0.5 * width / std::max(half_w, 1e-300),
                                          0.5 * height / std::max(half_h, 1e-300));
    return v;
}

Vec3 View::pixel(const Vec3& p) const {
    const Vec3 d = p - centre;
    return {0.5 * width + d.dot(right) * pixels_per_unit,
            0.5 * height - d.dot(up) * pixels_per_unit, d.dot(towards_viewer)};
}

std::array<unsigned char, 3> value_colour(double value, double lo, double hi) {
    if (!(value >= lo)) return {200, 0, 200};
    // Stops of the scale from lo to hi.
    static const std::array<std::array<double, 3>, 5> stops = {
        {{215, 25, 28}, {253, 174, 97}, {255, 255, 191}, {171, 221, 164}, {43, 131, 186}}};
    const double t = std::clamp((value - lo) / (hi - lo), 0.0, 1.0) * (stops.size() - 1);
    const std::size_t i = std::min(std::size_t(t), stops.size() - 2);
    const double f = t - double(i);
    std::array<unsigned char, 3> c;
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<unsigned char>(std::lround(stops[i][k] * (1 - f) + stops[i + 1][k] * f));
    return c;
}

// An RGB image and its depth buffer.
struct GridPictures::Canvas {
    std::string title;
    View view;
    bool cut = false;
    Vec3 normal = Vec3::UnitZ();  // of the cut plane n . x = offset
    double offset = 0;
    std::vector<unsigned char> rgb;
    std::vector<double> depth;
    // With several processes drawing (GridPictures::set_order): the order of what each pixel
    // shows, so that merging breaks depth ties as one process drawing in that order would.
    std::vector<std::uint32_t> order;
    std::uint32_t drawing = 0;

    Canvas(std::string title_, const View& v) : title(std::move(title_)), view(v) {
        rgb.assign(std::size_t(v.width) * v.height * 3, 255);
        depth.assign(std::size_t(v.width) * v.height, -std::numeric_limits<double>::infinity());
    }

    // Fills the screen triangle (x, y, depth), nearer than what is there, with colour c.
    void triangle(const Vec3& a, const Vec3& b, const Vec3& c,
                  const std::array<unsigned char, 3>& col) {
        const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
        if (!(std::abs(area) > 1e-12)) return;
        const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
        const int x1 = std::min(view.width - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
        const int y1 = std::min(view.height - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                const double wa =
                    ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
                const double wb =
                    ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
                const double wc = 1 - wa - wb;
                if (wa < 0 || wb < 0 || wc < 0) continue;
                put(x, y, wa * a.z() + wb * b.z() + wc * c.z(), col);
            }
    }

    // A line from a to b, drawn where it is not behind what is there by more than `bias`.
    void line(const Vec3& a, const Vec3& b, const std::array<unsigned char, 3>& col, double bias) {
        const int steps =
            int(std::ceil(std::max(std::abs(b.x() - a.x()), std::abs(b.y() - a.y())))) + 1;
        for (int s = 0; s <= steps; ++s) {
            const Vec3 p = a + (b - a) * (double(s) / steps);
            put(int(std::floor(p.x())), int(std::floor(p.y())), p.z() + bias, col);
        }
    }

    void put(int x, int y, double z, const std::array<unsigned char, 3>& col) {
        if (x < 0 || y < 0 || x >= view.width || y >= view.height) return;
        const std::size_t at = std::size_t(y) * view.width + x;
        if (!(z >= depth[at])) return;
        depth[at] = z;
        for (int k = 0; k < 3; ++k) rgb[3 * at + k] = col[k];
        if (!order.empty()) order[at] = drawing;
    }

    std::string png() const {
        vtkNew<vtkImageData> image;
        image->SetDimensions(view.width, view.height, 1);
        image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
        auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
        for (int y = 0; y < view.height; ++y)  // VTK's rows run bottom up
            std::copy_n(&rgb[std::size_t(view.height - 1 - y) * view.width * 3], view.width * 3,
                        out + std::size_t(y) * view.width * 3);
        vtkNew<vtkPNGWriter> writer;
        writer->SetInputData(image);
        writer->WriteToMemoryOn();
        writer->Write();
        vtkUnsignedCharArray* bytes = writer->GetResult();
        return std::string(reinterpret_cast<const char*>(bytes->GetPointer(0)),
                           std::size_t(bytes->GetNumberOfTuples()));
    }
};

namespace {

// Darkens a colour by a shading factor in (0, 1].
std::array<unsigned char, 3> shaded(std::array<unsigned char, 3> c, double factor) {
    for (auto& k : c) k = static_cast<unsigned char>(std::lround(k * factor));
    return c;
}

// The colour of a cell's edges over its face colour: the darker the larger the cell is on
// the picture (`pixels` across), none under 2 pixels, so that small cells fade into their
// colour instead of blackening the picture.
std::array<unsigned char, 3> edge_colour(const std::array<unsigned char, 3>& face, double pixels) {
    const double strength = std::clamp((pixels - 2) / 8, 0.0, 1.0);
    return shaded(face, 1 - 0.75 * strength);
}

std::string fmt_cut(const char* axis, double at) {
    return fmt::format("cut at {} = {:.4g}", axis, at);
}

bool much_larger(const Box3& domain, const Box3& wall) {
    return (domain.hi - domain.lo).norm() > 3 * (wall.hi - wall.lo).norm();
}

}  // namespace

GridPictures::GridPictures(const Box3& wall_box, const Box3& domain_box, double lo, double hi,
                           int size)
    : lo_(lo), hi_(hi) {
    const int w = size, h = size * 3 / 4;
    const std::array<std::pair<const char*, std::pair<Vec3, Vec3>>, 4> views = {{
        {"wall, from the front right", {Vec3(1, -1, 0.7), Vec3::UnitZ()}},
        {"wall, from the back left", {Vec3(-1, 1, 0.7), Vec3::UnitZ()}},
        {"wall, from above (+z)", {Vec3::UnitZ(), Vec3::UnitY()}},
        {"wall, from below (-z)", {-Vec3::UnitZ(), Vec3::UnitY()}},
    }};
    for (const auto& [title, dir] : views)
        wall_.emplace_back(title, View::framing(wall_box, dir.first, dir.second, w, h));
    // The planes pass a little off the centre, so that they do not run along the grid
    // planes of a symmetric grid (a cut along cell faces draws nothing clear).
    const Vec3 c = wall_box.center() + 0.0073 * (wall_box.hi - wall_box.lo);
    const auto add_cut = [&](const std::string& title, const Box3& frame, const Vec3& normal,
                             const Vec3& up, double offset) {
        // The frame's section: the box flattened onto the plane.
        Box3 flat = frame;
        for (int k = 0; k < 3; ++k)
            if (normal[k] != 0) flat.lo[k] = flat.hi[k] = offset;
        Canvas canvas(title, View::framing(flat, normal, up, w, h));
        canvas.cut = true;
        canvas.normal = normal;
        canvas.offset = offset;
        cuts_.push_back(std::move(canvas));
    };
    add_cut(fmt_cut("x", c.x()), wall_box, Vec3::UnitX(), Vec3::UnitZ(), c.x());
    add_cut(fmt_cut("y", c.y()), wall_box, -Vec3::UnitY(), Vec3::UnitZ(), c.y());
    add_cut(fmt_cut("z", c.z()), wall_box, Vec3::UnitZ(), Vec3::UnitY(), c.z());
    if (much_larger(domain_box, wall_box))
        add_cut(fmt_cut("z", c.z()) + ", whole domain", domain_box, Vec3::UnitZ(), Vec3::UnitY(),
                c.z());
}

GridPictures::~GridPictures() = default;
GridPictures::GridPictures(GridPictures&&) noexcept = default;
GridPictures& GridPictures::operator=(GridPictures&&) noexcept = default;

void GridPictures::add_wall_face(const std::array<Vec3, 4>& q, double value) {
    const std::array<unsigned char, 3> base = value_colour(value, lo_, hi_);
    Vec3 n = (q[2] - q[0]).cross(q[3] - q[1]);
    if (q[3] == q[2]) n = (q[1] - q[0]).cross(q[2] - q[0]);
    const double len = n.norm();
    for (Canvas& c : wall_) {
        const double light = len > 0 ? std::abs(n.dot(c.view.towards_viewer)) / len : 1;
        const std::array<unsigned char, 3> col = shaded(base, 0.45 + 0.55 * light);
        std::array<Vec3, 4> s;
        for (int k = 0; k < 4; ++k) s[k] = c.view.pixel(q[k]);
        c.triangle(s[0], s[1], s[2], col);
        if (q[3] != q[2]) c.triangle(s[0], s[2], s[3], col);
        const int corners = q[3] == q[2] ? 3 : 4;
        double smallest = 1e300;
        for (int k = 0; k < corners; ++k)
            smallest = std::min(smallest, (s[(k + 1) % corners] - s[k]).head<2>().norm());
        if (smallest < 2) continue;
        const double bias = 1e-3 * (c.view.width / c.view.pixels_per_unit);
        for (int k = 0; k < corners; ++k)
            c.line(s[k], s[(k + 1) % corners], edge_colour(col, smallest), bias);
    }
}

void GridPictures::add_cell(const Vec3* corners, int count, double value) {
    static const std::array<std::array<int, 2>, 12> hex_edges = {{{0, 1},
                                                                  {1, 2},
                                                                  {2, 3},
                                                                  {3, 0},
                                                                  {4, 5},
                                                                  {5, 6},
                                                                  {6, 7},
                                                                  {7, 4},
                                                                  {0, 4},
                                                                  {1, 5},
                                                                  {2, 6},
                                                                  {3, 7}}};
    static const std::array<std::array<int, 2>, 6> tet_edges = {
        {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
    const std::array<int, 2>* edges = count == 8 ? hex_edges.data() : tet_edges.data();
    const int edge_count = count == 8 ? 12 : 6;
    for (Canvas& c : cuts_) {
        double dmin = 1e300, dmax = -1e300;
        std::array<double, 8> d{};
        for (int k = 0; k < count; ++k) {
            d[k] = corners[k].dot(c.normal) - c.offset;
            dmin = std::min(dmin, d[k]);
            dmax = std::max(dmax, d[k]);
        }
        if (!(dmin < 0 && dmax >= 0)) continue;
        // Where the plane crosses the cell's edges, ordered round their mean on the picture.
        std::array<Vec3, 12> at;
        int n = 0;
        for (int e = 0; e < edge_count; ++e) {
            const double da = d[edges[e][0]], db = d[edges[e][1]];
            if ((da < 0) == (db < 0)) continue;
            const double t = da / (da - db);
            at[n++] = c.view.pixel(corners[edges[e][0]] +
                                   t * (corners[edges[e][1]] - corners[edges[e][0]]));
        }
        if (n < 3) continue;
        Vec3 mean = Vec3::Zero();
        for (int k = 0; k < n; ++k) mean += at[k];
        mean /= n;
        std::sort(at.begin(), at.begin() + n, [&](const Vec3& a, const Vec3& b) {
            return std::atan2(a.y() - mean.y(), a.x() - mean.x()) <
                   std::atan2(b.y() - mean.y(), b.x() - mean.x());
        });
        for (int k = 0; k < n; ++k) at[k].z() = 0;  // one plane: the later cell is drawn over
        const std::array<unsigned char, 3> col = value_colour(value, lo_, hi_);
        for (int k = 1; k + 1 < n; ++k) c.triangle(at[0], at[k], at[k + 1], col);
        double extent = 0;
        for (int k = 0; k < n; ++k) extent = std::max(extent, (at[k] - mean).head<2>().norm());
        if (extent < 1) continue;
        for (int k = 0; k < n; ++k) c.line(at[k], at[(k + 1) % n], edge_colour(col, 2 * extent), 1);
    }
}

void GridPictures::add_block(const BlockGrid& grid, const Block& block, const double* values,
                             bool all_boundary) {
    const Dims d = block.cells();
    for_each_cell(block, [&](int i, int j, int k, const std::array<Id, 8>& nodes) {
        std::array<Vec3, 8> p;
        for (int m = 0; m < 8; ++m) p[m] = grid.points[nodes[m]];
        const double value = values[d.flat(i, j, k)];
        add_cell(p.data(), 8, value);
        for (int f = 0; f < 6; ++f) {
            const bool shown =
                all_boundary ? !block.face_patch[f].empty() : block.face_patch[f] == "wall";
            if (!shown || !on_block_face(d, {i, j, k}, f)) continue;
            std::array<Vec3, 4> q;
            for (int m = 0; m < 4; ++m) q[m] = p[hex_faces[f][m]];
            add_wall_face(q, value);
        }
    });
}

void GridPictures::set_order(std::uint32_t order) {
    for (auto* canvases : {&wall_, &cuts_})
        for (Canvas& c : *canvases) {
            if (c.order.empty()) c.order.assign(c.depth.size(), 0);
            c.drawing = order;
        }
}

std::string GridPictures::pack() const {
    ByteWriter out;
    for (const auto* canvases : {&wall_, &cuts_})
        for (const Canvas& c : *canvases) {
            out.put(c.rgb), out.put(c.depth);
            out.put(c.order.empty() ? std::vector<std::uint32_t>(c.depth.size(), 0) : c.order);
        }
    return out.bytes();
}

void GridPictures::merge(const std::string& packed) {
    ByteReader in(packed);
    for (auto* canvases : {&wall_, &cuts_})
        for (Canvas& c : *canvases) {
            const std::vector<unsigned char> rgb = in.next<std::vector<unsigned char>>();
            const std::vector<double> depth = in.next<std::vector<double>>();
            const std::vector<std::uint32_t> order = in.next<std::vector<std::uint32_t>>();
            if (depth.size() != c.depth.size() || rgb.size() != c.rgb.size() ||
                order.size() != depth.size())
                throw std::runtime_error("pictures of another size cannot be merged");
            if (c.order.empty()) c.order.assign(c.depth.size(), 0);
            // The nearer wins; at equal depth, what was drawn later in the order.
            for (std::size_t at = 0; at < depth.size(); ++at) {
                if (!(depth[at] > c.depth[at] ||
                      (depth[at] == c.depth[at] && order[at] >= c.order[at])))
                    continue;
                c.depth[at] = depth[at];
                c.order[at] = order[at];
                for (int k = 0; k < 3; ++k) c.rgb[3 * at + k] = rgb[3 * at + k];
            }
        }
}

std::vector<Picture> GridPictures::pictures() const {
    std::vector<Picture> out;
    for (const std::vector<Canvas>* group : {&wall_, &cuts_})
        for (const Canvas& c : *group) out.push_back({c.title, c.view, c.cut, c.png()});
    return out;
}

}  // namespace hexmesh

// PLY reader (ASCII and binary little-endian): the x y z of element "vertex" and the index
// list of element "face"; other properties and elements are read past and dropped.
#include <fmt/format.h>

#include <cctype>

#include "io/ply_format.h"
#include "io/surface_formats.h"

namespace hexmesh::surface_io {
namespace {

using ply::Type;

// Reads values one by one from the body, binary or ASCII, tracking where it is for messages.
class BodyReader {
  public:
    // first_line: the line number of `start` (ASCII messages name lines).
    BodyReader(const std::string& data, size_t start, long long first_line, bool binary,
               const SurfaceBuilder& builder)
        : data_(data), at_(start), line_(first_line), binary_(binary), builder_(builder) {}

    // Binary: `where` names the element; ASCII: it is set to the line of the value.
    double next(Type type, Place& where) {
        return binary_ ? next_binary(type, where) : next_ascii(where);
    }

  private:
    double next_binary(Type type, Place where) {
        const size_t n = ply::type_size(type);
        if (at_ + n > data_.size()) builder_.fail(where, "truncated binary PLY data");
        const double v = ply::read_binary(data_.data() + at_, type);
        at_ += n;
        return v;
    }

    double next_ascii(Place& where) {
        while (at_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[at_]))) {
            if (data_[at_] == '\n') ++line_;
            ++at_;
        }
        const size_t start = at_;
        while (at_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[at_]))) ++at_;
        where = {"line", line_};
        if (at_ == start) builder_.fail(where, "truncated ASCII PLY data");
        double v = 0;
        const std::string_view token(data_.data() + start, at_ - start);
        if (!parse_double(token, v))
            builder_.fail(where, fmt::format("expected a number, got '{}'",
                                             std::string(token.substr(0, 20))));
        return v;
    }

    const std::string& data_;
    size_t at_;
    long long line_;
    bool binary_;
    const SurfaceBuilder& builder_;
};

}  // namespace

TriangleSurface read_ply(const std::string& data, SurfaceBuilder& builder) {
    const ply::Header header = ply::read_header(builder.file(), data);
    BodyReader reader(data, header.body, header.body_line, header.binary, builder);
    bool has_faces = false;
    std::vector<int> face;
    for (const ply::Element& e : header.elements) {
        const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
        int axis_of[3] = {-1, -1, -1};  // property index of x, y, z
        for (size_t k = 0; k < e.properties.size(); ++k)
            for (int a = 0; a < 3; ++a)
                if (e.properties[k].name == std::string(1, char('x' + a))) axis_of[a] = int(k);
        if (is_vertex && (axis_of[0] < 0 || axis_of[1] < 0 || axis_of[2] < 0))
            builder.fail({}, "PLY element 'vertex' lacks one of the properties x, y, z");
        has_faces = has_faces || (is_face && e.count > 0);
        for (long long n = 0; n < e.count; ++n) {
            Place where{is_face ? "face" : e.name == "vertex" ? "vertex" : "element", n + 1};
            Vec3 p = Vec3::Zero();
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const ply::Property& prop = e.properties[k];
                if (!prop.is_list) {
                    const double v = reader.next(prop.type, where);
                    for (int a = 0; a < 3; ++a)
                        if (axis_of[a] == int(k)) p[a] = v;
                    continue;
                }
                const double count = reader.next(prop.count_type, where);
                if (!(count >= 0 && count < 1e6))
                    builder.fail(where, fmt::format("bad list length {}", count));
                const bool indices =
                    is_face && (prop.name == "vertex_indices" || prop.name == "vertex_index");
                face.clear();
                for (int m = 0; m < int(count); ++m) {
                    const double id = reader.next(prop.type, where);
                    if (indices) face.push_back(id >= 0 && id < 2e9 ? int(id) : -1);
                }
                if (indices) builder.add_polygon(face, where);
            }
            if (is_vertex) builder.add_point(p, where);
        }
    }
    if (!has_faces) builder.fail({}, "not a surface: a PLY file without faces (a point cloud?)");
    return builder.finish();
}

}  // namespace hexmesh::surface_io

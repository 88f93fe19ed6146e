// Point clouds with normals: PLY (ASCII, binary little-endian) and XYZ text.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "io/ply_format.h"
#include "io/sample_readers.h"
#include "io/surface_formats.h"

namespace hexmesh {
namespace {

using surface_io::for_each_line;
using surface_io::parse_double;
using surface_io::split_tokens;

// `where`: "line 12" or "vertex 7".
void add_point(OrientedPoints& cloud, const double (&v)[6], const std::string& path,
               const std::string& where) {
    for (double x : v)
        if (!std::isfinite(x))
            throw InputError(
                fmt::format("{}: {}: coordinates and normals must be finite "
                            "numbers, got {}",
                            path, where, x));
    const Vec3 n(v[3], v[4], v[5]);
    if (!(n.norm() > 0))
        throw InputError(
            fmt::format("{}: {}: zero normal (nx ny nz must point out of the body)", path, where));
    cloud.points.emplace_back(v[0], v[1], v[2]);
    cloud.normals.push_back(n);
}

OrientedPoints read_xyz(const std::string& path, const std::string& data) {
    OrientedPoints cloud;
    std::vector<std::string_view> tokens;
    for_each_line(data, [&](long long number, std::string_view line) {
        line = line.substr(0, line.find('#'));
        split_tokens(line, tokens);
        if (tokens.empty()) return true;
        const std::string where = fmt::format("line {}", number);
        if (tokens.size() != 6)
            throw InputError(fmt::format("{}: {}: expected 6 numbers 'x y z nx ny nz', got {}{}",
                                         path, where, tokens.size(),
                                         tokens.size() == 3 ? " (missing normals?)" : ""));
        double v[6];
        for (int k = 0; k < 6; ++k)
            if (!parse_double(tokens[k], v[k]))
                throw InputError(fmt::format("{}: {}: expected a number, got '{}'", path, where,
                                             std::string(tokens[k].substr(0, 20))));
        add_point(cloud, v, path, where);
        return true;
    });
    return cloud;
}

using ply::Property;
using ply::Type;

// Values of the PLY body in order, ASCII or binary; `where` says where the last one was.
class PlyBody {
  public:
    PlyBody(const std::string& path, const std::string& data, size_t at, long long line,
            bool binary)
        : path_(path),
          data_(data),
          at_(at),
          line_(line),
          binary_(binary),
          where_(fmt::format("line {}", line)) {}

    double next(Type type, const std::string& element, long long index) {
        if (binary_) {
            where_ = fmt::format("{} {}", element, index);
            const size_t n = ply::type_size(type);
            if (at_ + n > data_.size()) fail("truncated binary PLY data");
            const double v = ply::read_binary(data_.data() + at_, type);
            at_ += n;
            return v;
        }
        while (at_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[at_])))
            line_ += data_[at_++] == '\n';
        const size_t start = at_;
        while (at_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[at_]))) ++at_;
        if (at_ == start) fail("truncated ASCII PLY data");  // at the line of the last value
        where_ = fmt::format("line {}", line_);
        double v = 0;
        const std::string_view token(data_.data() + start, at_ - start);
        if (!parse_double(token, v))
            fail(fmt::format("expected a number, got '{}'", std::string(token.substr(0, 20))));
        return v;
    }
    const std::string& where() const { return where_; }
    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(fmt::format("{}: {}: {}", path_, where_, message));
    }

  private:
    const std::string& path_;
    const std::string& data_;
    size_t at_;
    long long line_;
    bool binary_;
    std::string where_;
};

OrientedPoints read_point_ply(const std::string& path, const std::string& data) {
    const ply::Header header = ply::read_header(path, data, true);
    static const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
    OrientedPoints cloud;
    PlyBody reader(path, data, header.body, header.body_line, header.binary);
    bool has_vertices = false;
    for (const ply::Element& e : header.elements) {
        const bool is_vertex = e.name == "vertex";
        int slot_of[64];  // property index -> 0..5 (x..nz) or -1
        if (e.properties.size() > 64) throw InputError(path + ": too many PLY properties");
        if (is_vertex) {
            has_vertices = true;
            for (int a = 0; a < 6; ++a) {
                const auto it = std::find_if(e.properties.begin(), e.properties.end(),
                                             [&](const Property& p) { return p.name == names[a]; });
                if (it == e.properties.end() || it->is_list)
                    throw InputError(fmt::format(
                        "{}: PLY element 'vertex' lacks the property {}{}", path, names[a],
                        a >= 3 ? " (a point cloud needs normals nx ny nz)" : ""));
            }
        }
        for (size_t k = 0; k < e.properties.size(); ++k) {
            slot_of[k] = -1;
            for (int a = 0; a < 6 && is_vertex; ++a)
                if (e.properties[k].name == names[a]) slot_of[k] = a;
        }
        for (long long n = 1; n <= e.count; ++n) {
            double v[6] = {0, 0, 0, 0, 0, 0};
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const Property& prop = e.properties[k];
                if (!prop.is_list) {
                    const double value = reader.next(prop.type, e.name, n);
                    if (slot_of[k] >= 0) v[slot_of[k]] = value;
                    continue;
                }
                const double count = reader.next(prop.count_type, e.name, n);
                if (!(count >= 0 && count < 1e6))
                    reader.fail(fmt::format("bad list length {}", count));
                for (int m = 0; m < int(count); ++m) reader.next(prop.type, e.name, n);
            }
            if (is_vertex) add_point(cloud, v, path, reader.where());
        }
    }
    if (!has_vertices) throw InputError(path + ": PLY file without element 'vertex'");
    return cloud;
}

}  // namespace

OrientedPoints read_point_cloud(const std::string& path) {
    const std::string extension = surface_io::file_extension(path);
    if (extension != "ply" && extension != "xyz")
        throw InputError(
            fmt::format("{}: unknown point cloud format '{}' (expected a .ply or .xyz file)", path,
                        extension.empty() ? "no extension" : "." + extension));
    const std::string data = surface_io::read_file(path);
    OrientedPoints cloud = extension == "ply" ? read_point_ply(path, data) : read_xyz(path, data);
    if (cloud.points.empty()) throw InputError(path + ": no point in the file");
    return cloud;
}

GeometryFileKind geometry_file_kind(const std::string& path) {
    const std::string extension = surface_io::file_extension(path);
    if (extension == "stl" || extension == "obj" || extension == "off")
        return GeometryFileKind::surface;
    if (extension == "xyz") return GeometryFileKind::points;
    if (extension != "ply") return GeometryFileKind::sections;
    const ply::Header header = ply::read_header(path, surface_io::read_file(path), true);
    // Points need normals; a PLY with neither faces nor normals is read as a surface, whose
    // reader names what is missing.
    bool faces = false, normals = false;
    for (const ply::Element& e : header.elements) {
        faces |= e.name == "face" && e.count > 0;
        if (e.name == "vertex")
            normals = std::any_of(e.properties.begin(), e.properties.end(),
                                  [](const ply::Property& p) { return p.name == "nx"; });
    }
    return !faces && normals ? GeometryFileKind::points : GeometryFileKind::surface;
}

}  // namespace hexmesh

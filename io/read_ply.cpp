// PLY reader (ASCII and binary little-endian): the x y z of element "vertex" and the index
// list of element "face"; other properties and elements are read past and dropped.
#include <cstdint>
#include <cstring>
#include <fmt/format.h>

#include "io/surface_formats.h"

namespace hexmesh::surface_io {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_type(std::string_view name, Type& type) {
    static const struct { const char* name; Type type; } names[] = {
        {"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},  {"uint8", Type::u8},
        {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
        {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},  {"uint32", Type::u32},
        {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
    for (const auto& n : names)
        if (name == n.name) return type = n.type, true;
    return false;
}

size_t type_size(Type t) {
    switch (t) {
        case Type::i8: case Type::u8: return 1;
        case Type::i16: case Type::u16: return 2;
        case Type::i32: case Type::u32: case Type::f32: return 4;
        case Type::f64: return 8;
    }
    return 0;
}

struct Property {
    std::string name;
    Type type = Type::f32;
    bool is_list = false;
    Type count_type = Type::u8;
};

struct Element {
    std::string name;
    long long count = 0;
    std::vector<Property> properties;
};

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
        const size_t n = type_size(type);
        if (at_ + n > data_.size()) builder_.fail(where, "truncated binary PLY data");
        unsigned char b[8];
        std::memcpy(b, data_.data() + at_, n);
        at_ += n;
        switch (type) {
            case Type::i8: return static_cast<std::int8_t>(b[0]);
            case Type::u8: return b[0];
            case Type::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
            case Type::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
            case Type::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
            case Type::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
            case Type::f32: { float v; std::memcpy(&v, b, 4); return v; }
            case Type::f64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
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
    std::vector<Element> elements;
    std::vector<std::string_view> tokens;
    std::string format;
    size_t body = std::string::npos;
    long long header_lines = 0;
    for_each_line(data, [&](long long number, std::string_view line) {
        const Place where{"line", number};
        split_tokens(line, tokens);
        if (number == 1 && (tokens.size() != 1 || tokens[0] != "ply"))
            builder.fail(where, "not a PLY file: the first line must be 'ply'");
        if (tokens.empty() || tokens[0] == "ply" || tokens[0] == "comment" || tokens[0] == "obj_info")
            return true;
        if (tokens[0] == "format") {
            if (tokens.size() < 2) builder.fail(where, "expected 'format ascii|binary_little_endian 1.0'");
            format = std::string(tokens[1]);
            if (format != "ascii" && format != "binary_little_endian")
                builder.fail(where, fmt::format("unsupported PLY format '{}' (ascii or "
                                                "binary_little_endian)", format));
        } else if (tokens[0] == "element") {
            long long count = 0;
            if (tokens.size() != 3 || !parse_int(tokens[2], count) || count < 0)
                builder.fail(where, "expected 'element NAME COUNT'");
            elements.push_back({std::string(tokens[1]), count, {}});
        } else if (tokens[0] == "property") {
            Property p;
            const bool list = tokens.size() == 5 && tokens[1] == "list";
            if (elements.empty() || (tokens.size() != 3 && !list) ||
                (list && (!parse_type(tokens[2], p.count_type) || !parse_type(tokens[3], p.type))) ||
                (!list && !parse_type(tokens[1], p.type)))
                builder.fail(where, "expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
            p.is_list = list;
            p.name = std::string(tokens.back());
            elements.back().properties.push_back(p);
        } else if (tokens[0] == "end_header") {
            body = static_cast<size_t>(line.data() + line.size() - data.data());
            body = data.find('\n', body);
            body = body == std::string::npos ? data.size() : body + 1;
            header_lines = number;
            return false;
        } else {
            builder.fail(where, fmt::format("unexpected PLY header line '{}'",
                                            std::string(tokens[0].substr(0, 20))));
        }
        return true;
    });
    if (body == std::string::npos) builder.fail({}, "not a PLY file: no 'end_header'");
    if (format.empty()) builder.fail({}, "PLY header has no 'format' line");

    BodyReader reader(data, body, header_lines + 1, format != "ascii", builder);
    bool has_faces = false;
    std::vector<int> face;
    for (const Element& e : elements) {
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
                const Property& prop = e.properties[k];
                if (!prop.is_list) {
                    const double v = reader.next(prop.type, where);
                    for (int a = 0; a < 3; ++a)
                        if (axis_of[a] == int(k)) p[a] = v;
                    continue;
                }
                const double count = reader.next(prop.count_type, where);
                if (!(count >= 0 && count < 1e6))
                    builder.fail(where, fmt::format("bad list length {}", count));
                const bool indices = is_face && (prop.name == "vertex_indices" || prop.name == "vertex_index");
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

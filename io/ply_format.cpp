#include "io/ply_format.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

#include "io/surface_formats.h"

namespace hexmesh::ply {

bool parse_type(std::string_view name, Type& type) {
    static const struct {
        const char* name;
        Type type;
    } names[] = {{"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},
                 {"uint8", Type::u8},   {"short", Type::i16},   {"int16", Type::i16},
                 {"ushort", Type::u16}, {"uint16", Type::u16},  {"int", Type::i32},
                 {"int32", Type::i32},  {"uint", Type::u32},    {"uint32", Type::u32},
                 {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64},
                 {"float64", Type::f64}};
    for (const auto& n : names)
        if (name == n.name) return type = n.type, true;
    return false;
}

size_t type_size(Type t) {
    switch (t) {
        case Type::i8:
        case Type::u8:
            return 1;
        case Type::i16:
        case Type::u16:
            return 2;
        case Type::i32:
        case Type::u32:
        case Type::f32:
            return 4;
        case Type::f64:
            return 8;
    }
    return 0;
}

double read_binary(const char* b, Type t) {
    switch (t) {
        case Type::i8:
            return static_cast<std::int8_t>(*b);
        case Type::u8:
            return static_cast<std::uint8_t>(*b);
        case Type::i16: {
            std::int16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::u16: {
            std::uint16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::i32: {
            std::int32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::u32: {
            std::uint32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::f32: {
            float v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::f64: {
            double v;
            std::memcpy(&v, b, 8);
            return v;
        }
    }
    return 0;
}

Header read_header(const std::string& path, const std::string& data,
                   bool bare_format_is_unsupported) {
    using surface_io::parse_int;
    using surface_io::split_tokens;
    Header header;
    std::vector<Element>& elements = header.elements;
    std::vector<std::string_view> tokens;
    std::string format;
    size_t body = std::string::npos;
    surface_io::for_each_line(data, [&](long long number, std::string_view line) {
        const auto fail = [&](const std::string& message) {
            throw InputError(fmt::format("{}: line {}: {}", path, number, message));
        };
        split_tokens(line, tokens);
        if (number == 1 && (tokens.size() != 1 || tokens[0] != "ply"))
            fail("not a PLY file: the first line must be 'ply'");
        if (tokens.empty() || tokens[0] == "ply" || tokens[0] == "comment" ||
            tokens[0] == "obj_info")
            return true;
        if (tokens[0] == "format") {
            if (tokens.size() < 2 && !bare_format_is_unsupported)
                fail("expected 'format ascii|binary_little_endian 1.0'");
            format = tokens.size() < 2 ? "" : std::string(tokens[1]);
            if (format != "ascii" && format != "binary_little_endian")
                fail(fmt::format("unsupported PLY format '{}' (ascii or binary_little_endian)",
                                 format));
        } else if (tokens[0] == "element") {
            long long count = 0;
            if (tokens.size() != 3 || !parse_int(tokens[2], count) || count < 0)
                fail("expected 'element NAME COUNT'");
            elements.push_back({std::string(tokens[1]), count, {}});
        } else if (tokens[0] == "property") {
            Property p;
            p.is_list = tokens.size() == 5 && tokens[1] == "list";
            if (elements.empty() || (tokens.size() != 3 && !p.is_list) ||
                (p.is_list &&
                 (!parse_type(tokens[2], p.count_type) || !parse_type(tokens[3], p.type))) ||
                (!p.is_list && !parse_type(tokens[1], p.type)))
                fail("expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
            p.name = std::string(tokens.back());
            elements.back().properties.push_back(p);
        } else if (tokens[0] == "end_header") {
            body = data.find('\n', static_cast<size_t>(line.data() - data.data()));
            body = body == std::string::npos ? data.size() : body + 1;
            header.body_line = number + 1;
            return false;
        } else {
            fail(fmt::format("unexpected PLY header line '{}'",
                             std::string(tokens[0].substr(0, 20))));
        }
        return true;
    });
    if (body == std::string::npos) throw InputError(path + ": not a PLY file: no 'end_header'");
    if (format.empty()) throw InputError(path + ": PLY header has no 'format' line");
    // Items of no property take no bytes: nothing bounds their count by the file's size.
    for (const Element& e : elements)
        if (e.count > 0 && e.properties.empty())
            throw InputError(fmt::format("{}: PLY element '{}' declares {} items but no property",
                                         path, e.name, e.count));
    header.body = body;
    header.binary = format != "ascii";
    return header;
}

}  // namespace hexmesh::ply

// Internal to the PLY readers (surfaces, point clouds): the header and the property types.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace hexmesh::ply {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

// Parses a PLY type name ("uchar", "float32", ...); false if it is none.
bool parse_type(std::string_view name, Type& type);
// Bytes of a value of type `t` in binary data.
size_t type_size(Type t);
// Decodes the little-endian value of type `t` at `bytes` (type_size(t) bytes).
double read_binary(const char* bytes, Type t);

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

struct Header {
    std::vector<Element> elements;
    bool binary = false;      // binary little-endian, else ASCII
    size_t body = 0;          // offset of the first byte after the 'end_header' line
    long long body_line = 0;  // line number of `body` (ASCII messages name lines)
};

// Reads the header of PLY `data`. Throws InputError "<path>: line N: ..." for a bad header
// line and "<path>: ..." for a missing 'end_header' or 'format'. A 'format' line without a
// format name fails as "expected 'format ...'", or, with `bare_format_is_unsupported`, as
// the unsupported format ''.
Header read_header(const std::string& path, const std::string& data,
                   bool bare_format_is_unsupported = false);

}  // namespace hexmesh::ply

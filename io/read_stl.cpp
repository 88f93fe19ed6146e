// STL reader: binary or ASCII, told apart by size and content, not by the word "solid"
// (many binary exporters start their 80-byte header with it). Corners are merged exactly.
#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "io/surface_formats.h"

namespace hexmesh::surface_io {
namespace {

struct ExactKey {
    double x, y, z;
    bool operator==(const ExactKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct ExactKeyHash {
    size_t operator()(const ExactKey& k) const {
        const std::hash<double> h;
        size_t s = h(k.x);
        s ^= h(k.y) + 0x9e3779b97f4a7c15ULL + (s << 6) + (s >> 2);
        s ^= h(k.z) + 0x9e3779b97f4a7c15ULL + (s << 6) + (s >> 2);
        return s;
    }
};

// Gives identical coordinates one point id (-0.0 and 0.0 count as equal).
class PointMerger {
  public:
    explicit PointMerger(SurfaceBuilder& builder) : builder_(builder) {}
    int id(const Vec3& p, Place where) {
        const auto [it, inserted] = ids_.try_emplace(ExactKey{p.x(), p.y(), p.z()}, 0);
        if (inserted) it->second = builder_.add_point(p, where);
        return it->second;
    }

  private:
    SurfaceBuilder& builder_;
    std::unordered_map<ExactKey, int, ExactKeyHash> ids_;
};

bool looks_like_text(const std::string& data) {
    const size_t n = std::min<size_t>(data.size(), 1024);
    for (size_t k = 0; k < n; ++k) {
        const unsigned char c = data[k];
        if (c < 9 || (c > 13 && c < 32) || c == 127) return false;
    }
    return true;
}

bool starts_with_solid(const std::string& data) {
    size_t k = 0;
    while (k < data.size() && std::isspace(static_cast<unsigned char>(data[k]))) ++k;
    return data.compare(k, 5, "solid") == 0;
}

TriangleSurface read_binary(const std::string& data, std::uint32_t count, SurfaceBuilder& builder) {
    PointMerger merger(builder);
    for (std::uint32_t t = 0; t < count; ++t) {
        const char* record = data.data() + 84 + 50 * size_t(t);
        float v[9];
        std::memcpy(v, record + 12, sizeof v);  // skip the stored normal; little-endian host
        const Place where{"triangle", t + 1};
        int ids[3];
        for (int c = 0; c < 3; ++c)
            ids[c] = merger.id(Vec3(v[3 * c], v[3 * c + 1], v[3 * c + 2]), where);
        builder.add_triangle(ids[0], ids[1], ids[2], where);
    }
    return builder.finish();
}

TriangleSurface read_ascii(const std::string& data, SurfaceBuilder& builder) {
    PointMerger merger(builder);
    std::vector<std::string_view> tokens;
    std::vector<int> loop;
    bool in_loop = false;
    for_each_line(data, [&](long long number, std::string_view line) {
        const Place where{"line", number};
        split_tokens(line, tokens);
        if (tokens.empty()) return true;
        const std::string_view key = tokens[0];
        if (key == "vertex") {
            if (!in_loop) builder.fail(where, "'vertex' outside an 'outer loop'");
            Vec3 p;
            if (tokens.size() != 4 || !parse_double(tokens[1], p.x()) ||
                !parse_double(tokens[2], p.y()) || !parse_double(tokens[3], p.z()))
                builder.fail(where, "expected 'vertex X Y Z' with 3 numbers");
            loop.push_back(merger.id(p, where));
        } else if (key == "outer") {
            in_loop = true;
            loop.clear();
        } else if (key == "endloop") {
            if (loop.size() != 3)
                builder.fail(where, fmt::format("a facet needs 3 vertices, got {}", loop.size()));
            builder.add_triangle(loop[0], loop[1], loop[2], where);
            in_loop = false;
        } else if (key != "solid" && key != "endsolid" && key != "facet" && key != "endfacet") {
            builder.fail(where, fmt::format("not an ASCII STL file: unexpected '{}'",
                                            std::string(key.substr(0, 20))));
        }
        return true;
    });
    if (in_loop) builder.fail({}, "truncated ASCII STL: the last facet has no 'endloop'");
    return builder.finish();
}

}  // namespace

TriangleSurface read_stl(const std::string& data, SurfaceBuilder& builder) {
    const bool text = looks_like_text(data);
    if (text && starts_with_solid(data)) return read_ascii(data, builder);
    if (text) builder.fail({}, "not an STL file: text that does not start with 'solid'");
    if (data.size() < 84)
        builder.fail({}, fmt::format("truncated binary STL: {} bytes, the header alone has 84",
                                     data.size()));
    std::uint32_t count;
    std::memcpy(&count, data.data() + 80, 4);
    const unsigned long long needed = 84 + 50ULL * count;
    if (data.size() < needed)
        builder.fail({}, fmt::format("truncated binary STL: the header announces {} triangles "
                                     "({} bytes), the file has {} bytes",
                                     count, needed, data.size()));
    return read_binary(data, count, builder);
}

}  // namespace hexmesh::surface_io

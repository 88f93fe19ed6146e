// OBJ and OFF readers: vertices and polygon faces (split into fans); everything else
// (normals, texture coordinates, groups, materials, colours) is skipped.
#include <fmt/format.h>

#include "io/surface_formats.h"

namespace hexmesh::surface_io {
namespace {

// "7", "7/2", "7//3", "7/2/3": 1-based, or negative = relative to the last vertex.
int obj_vertex_id(std::string_view token, int defined, const SurfaceBuilder& builder, Place where) {
    long long id = 0;
    if (!parse_int(token.substr(0, token.find('/')), id) || id == 0)
        builder.fail(where, fmt::format("expected a vertex index, got '{}'",
                                        std::string(token.substr(0, 20))));
    const long long zero_based = id > 0 ? id - 1 : defined + id;
    if (zero_based < 0 || zero_based >= defined)
        builder.fail(where, fmt::format("vertex index {} out of range ({} vertices defined so far)",
                                        id, defined));
    return static_cast<int>(zero_based);
}

bool parse_point(const std::vector<std::string_view>& tokens, size_t first, Vec3& p) {
    return tokens.size() >= first + 3 && parse_double(tokens[first], p.x()) &&
           parse_double(tokens[first + 1], p.y()) && parse_double(tokens[first + 2], p.z());
}

}  // namespace

TriangleSurface read_obj(const std::string& data, SurfaceBuilder& builder) {
    std::vector<std::string_view> tokens;
    std::vector<int> face;
    for_each_line(data, [&](long long number, std::string_view line) {
        const Place where{"line", number};
        split_tokens(line, tokens);
        if (tokens.empty()) return true;
        if (tokens[0] == "v") {
            Vec3 p;
            if (!parse_point(tokens, 1, p))
                builder.fail(where, "expected 'v X Y Z' with 3 numbers");
            builder.add_point(p, where);
        } else if (tokens[0] == "f") {
            face.clear();
            for (size_t k = 1; k < tokens.size(); ++k)
                face.push_back(obj_vertex_id(tokens[k], builder.num_points(), builder, where));
            builder.add_polygon(face, where);
        }
        return true;
    });
    return builder.finish();
}

TriangleSurface read_off(const std::string& data, SurfaceBuilder& builder) {
    std::vector<std::string_view> tokens;
    enum class Stage { header, counts, vertices, faces, done } stage = Stage::header;
    long long vertices = 0, faces = 0, seen = 0;
    std::vector<int> face;
    for_each_line(data, [&](long long number, std::string_view line) {
        const Place where{"line", number};
        line = line.substr(0, line.find('#'));
        split_tokens(line, tokens);
        if (tokens.empty()) return true;
        size_t first = 0;
        if (stage == Stage::header) {
            const std::string_view key = tokens[0];
            if (key.size() < 3 || key.substr(key.size() - 3) != "OFF")
                builder.fail(where, fmt::format("not an OFF file: expected 'OFF', got '{}'",
                                                std::string(key.substr(0, 20))));
            stage = Stage::counts;
            if (tokens.size() == 1) return true;
            first = 1;  // counts on the header line
        }
        if (stage == Stage::counts) {
            if (tokens.size() < first + 2 || !parse_int(tokens[first], vertices) ||
                !parse_int(tokens[first + 1], faces) || vertices < 0 || faces < 0 ||
                vertices > (1LL << 30) || faces > (1LL << 30))
                builder.fail(where, "expected the counts 'VERTICES FACES EDGES'");
            stage = vertices > 0 ? Stage::vertices : Stage::faces;
            return true;
        }
        if (stage == Stage::vertices) {
            Vec3 p;
            if (!parse_point(tokens, 0, p)) builder.fail(where, "expected a vertex 'X Y Z'");
            builder.add_point(p, where);
            if (++seen == vertices) stage = Stage::faces, seen = 0;
            return true;
        }
        if (stage == Stage::faces) {
            long long n = 0;
            if (!parse_int(tokens[0], n) || n < 3 || tokens.size() < size_t(n) + 1)
                builder.fail(where, "expected a face 'N ID1 ... IDN' with N >= 3");
            face.clear();
            for (long long k = 1; k <= n; ++k) {
                long long id = 0;
                if (!parse_int(tokens[k], id) || id < 0 || id >= vertices)
                    builder.fail(where,
                                 fmt::format("vertex index '{}' out of range [0, {})",
                                             std::string(tokens[k].substr(0, 20)), vertices));
                face.push_back(static_cast<int>(id));
            }
            builder.add_polygon(face, where);
            if (++seen == faces) stage = Stage::done;
            return true;
        }
        return true;  // trailing data after the last face is ignored
    });
    if (stage == Stage::vertices || (stage == Stage::faces && faces > 0))
        builder.fail({}, fmt::format("truncated OFF file: expected {} vertices and {} faces",
                                     vertices, faces));
    return builder.finish();
}

}  // namespace hexmesh::surface_io

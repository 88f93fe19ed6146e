#include "io/surface_reader.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/surface_formats.h"

namespace hexmesh {
namespace surface_io {

constexpr double max_coordinate = 1e150;

void SurfaceBuilder::fail(Place where, const std::string& message) const {
    if (!where.unit) throw InputError(fmt::format("{}: {}", file_, message));
    throw InputError(fmt::format("{}: {} {}: {}", file_, where.unit, where.index, message));
}

int SurfaceBuilder::add_point(const Vec3& p, Place where) {
    if (!p.allFinite())
        fail(where, fmt::format("vertex coordinates must be finite numbers, got ({}, {}, {})",
                                p.x(), p.y(), p.z()));
    // Beyond 1e150 the products of two coordinates (areas, normals) overflow: the file's units
    // are wrong, and that, not a degenerate triangle further on, is what to say.
    if (p.cwiseAbs().maxCoeff() > max_coordinate)
        fail(where, fmt::format("vertex coordinates up to {:g} are supported, got ({}, {}, {})",
                                max_coordinate, p.x(), p.y(), p.z()));
    surface_.points.push_back(p);
    return num_points() - 1;
}

void SurfaceBuilder::add_triangle(int a, int b, int c, Place where) {
    const int n = num_points();
    for (int id : {a, b, c})
        if (id < 0 || id >= n)
            fail(where, fmt::format("vertex index {} out of range ({} vertices)", id, n));
    if (!allow_degenerate_) {
        const Vec3 &pa = surface_.points[a], &pb = surface_.points[b], &pc = surface_.points[c];
        const double longest =
            std::max({(pb - pa).squaredNorm(), (pc - pb).squaredNorm(), (pa - pc).squaredNorm()});
        if (!((pb - pa).cross(pc - pa).norm() > 1e-12 * longest))
            fail(where, fmt::format("zero-area triangle (corners ({}, {}, {}), ({}, {}, {}), "
                                    "({}, {}, {})); `hexmesh inspect` lists all of them",
                                    pa.x(), pa.y(), pa.z(), pb.x(), pb.y(), pb.z(), pc.x(), pc.y(),
                                    pc.z()));
    }
    surface_.triangles.push_back({a, b, c});
}

void SurfaceBuilder::add_polygon(const std::vector<int>& ids, Place where) {
    if (ids.size() < 3)
        fail(where, fmt::format("a face needs at least 3 vertices, got {}", ids.size()));
    for (size_t k = 1; k + 1 < ids.size(); ++k) add_triangle(ids[0], ids[k], ids[k + 1], where);
}

TriangleSurface SurfaceBuilder::finish() {
    if (surface_.triangles.empty()) fail({}, "not a surface: the file holds no triangle");
    return std::move(surface_);
}

void split_tokens(std::string_view line, std::vector<std::string_view>& tokens) {
    tokens.clear();
    size_t k = 0;
    while (k < line.size()) {
        while (k < line.size() && std::isspace(static_cast<unsigned char>(line[k]))) ++k;
        const size_t start = k;
        while (k < line.size() && !std::isspace(static_cast<unsigned char>(line[k]))) ++k;
        if (k > start) tokens.push_back(line.substr(start, k - start));
    }
}

bool parse_double(std::string_view token, double& value) {
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, value);
    return r.ec == std::errc() && r.ptr == end;
}

bool parse_int(std::string_view token, long long& value) {
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, value);
    return r.ec == std::errc() && r.ptr == end;
}

std::string file_extension(const std::string& path) {
    std::string extension;
    const auto dot = path.find_last_of('.');
    if (dot != std::string::npos && path.find('/', dot) == std::string::npos)
        extension = path.substr(dot + 1);
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return extension;
}

std::string read_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError(fmt::format("{}: is a folder, not a surface file", path));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open ({})", path, std::strerror(errno)));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw InputError(fmt::format("{}: cannot read", path));
    std::string data = buffer.str();
    if (data.empty()) throw InputError(fmt::format("{}: empty file", path));
    return data;
}

}  // namespace surface_io

TriangleSurface read_surface(const std::string& path, const SurfaceReadOptions& options) {
    using namespace surface_io;
    const std::string extension = file_extension(path);
    using Reader = TriangleSurface (*)(const std::string&, SurfaceBuilder&);
    Reader reader = extension == "stl"   ? read_stl
                    : extension == "obj" ? read_obj
                    : extension == "off" ? read_off
                    : extension == "ply" ? read_ply
                                         : nullptr;
    if (!reader)
        throw InputError(fmt::format(
            "{}: unknown surface format '{}' (expected a .stl, .obj, .off or .ply file)", path,
            extension.empty() ? "no extension" : "." + extension));

    const std::string data = read_file(path);
    SurfaceBuilder builder(path, options.allow_degenerate);
    return reader(data, builder);
}

}  // namespace hexmesh

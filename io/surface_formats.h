// Internal to the surface readers: the per-format parsers and the checks they share.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "io/surface_reader.h"

namespace hexmesh::surface_io {

// Where in the file a problem is: "line 12" for text, "triangle 7" for binary data.
struct Place {
    const char* unit = nullptr;  // "line", "triangle", "vertex", "face"; nullptr: whole file
    long long index = 0;         // 1-based
};

// Collects points and triangles, checking each one as it arrives, so that every error can
// name the place it comes from.
class SurfaceBuilder {
  public:
    SurfaceBuilder(std::string file, bool allow_degenerate)
        : file_(std::move(file)), allow_degenerate_(allow_degenerate) {}

    int num_points() const { return static_cast<int>(surface_.points.size()); }
    int add_point(const Vec3& p, Place where);                   // refuses NaN and infinity
    void add_triangle(int a, int b, int c, Place where);         // ids must exist already
    void add_polygon(const std::vector<int>& ids, Place where);  // a fan from ids[0]
    TriangleSurface finish();                                    // refuses an empty surface
    [[noreturn]] void fail(Place where, const std::string& message) const;
    const std::string& file() const { return file_; }

  private:
    std::string file_;
    bool allow_degenerate_;
    TriangleSurface surface_;
};

// Splits text into whitespace-separated tokens (string views into `line`).
void split_tokens(std::string_view line, std::vector<std::string_view>& tokens);

// Parses a whole token as a number; false if it is not one.
bool parse_double(std::string_view token, double& value);
bool parse_int(std::string_view token, long long& value);

// The extension of the file name in `path`, lower case, without the dot ("" if none).
std::string file_extension(const std::string& path);

// The whole file; throws InputError "<path>: cannot open (...)", "cannot read" or
// "empty file".
std::string read_file(const std::string& path);

// Calls visit(line_number, line) for each line of text (1-based, without the newline).
template <typename Visit>
void for_each_line(std::string_view text, Visit visit) {
    long long number = 0;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (!visit(++number, line)) return;
        start = end + 1;
    }
}

TriangleSurface read_stl(const std::string& data, SurfaceBuilder& builder);
TriangleSurface read_obj(const std::string& data, SurfaceBuilder& builder);
TriangleSurface read_off(const std::string& data, SurfaceBuilder& builder);
TriangleSurface read_ply(const std::string& data, SurfaceBuilder& builder);

}  // namespace hexmesh::surface_io

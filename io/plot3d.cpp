#include "io/plot3d.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unordered_map>

#include "io/file_sink.h"
#include "io/input_error.h"
#include "io/neutral_map.h"

namespace hexmesh {
namespace {

using json = nlohmann::json;

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE floats expected");

// Fortran's byte-count marker: 4-byte little-endian; records must fit in 2^31 - 1 bytes.
void put_marker(FileSink& out, Id bytes) {
    if (bytes > 0x7fffffff)
        throw std::runtime_error(fmt::format(
            "{}: a block of {} bytes exceeds Fortran's 2 GB record limit", out.path(), bytes));
    out.put(std::int32_t(bytes));
}

template <class Real>
void write_binary(const BlockGrid& grid, FileSink& out, bool fortran) {
    const Id nb = Id(grid.blocks.size());
    if (fortran) put_marker(out, 4);
    out.put(std::int32_t(nb));
    if (fortran) put_marker(out, 4);
    if (fortran) put_marker(out, 12 * nb);
    for (const Block& b : grid.blocks)
        for (int a = 0; a < 3; ++a) out.put(std::int32_t(b.nodes[a]));
    if (fortran) put_marker(out, 12 * nb);
    std::vector<Real> buffer;
    for (const Block& b : grid.blocks) {
        const Id n = b.nodes.count();
        if (fortran) put_marker(out, 3 * n * Id(sizeof(Real)));
        buffer.resize(n);
        for (int a = 0; a < 3; ++a) {
            for (Id m = 0; m < n; ++m) buffer[m] = Real(grid.points[b.node_ids[m]][a]);
            out.write(buffer.data(), buffer.size() * sizeof(Real));
        }
        if (fortran) put_marker(out, 3 * n * Id(sizeof(Real)));
    }
}

void write_ascii(const BlockGrid& grid, FileSink& out, bool single) {
    out.print("{}\n", grid.blocks.size());
    for (const Block& b : grid.blocks) out.print("{} {} {}\n", b.nodes.ni, b.nodes.nj, b.nodes.nk);
    for (const Block& b : grid.blocks)
        for (int a = 0; a < 3; ++a) {
            const Id n = b.nodes.count();
            for (Id m = 0; m < n; ++m) {
                const double x = grid.points[b.node_ids[m]][a];
                if (single)
                    out.print("{}", float(x));
                else
                    out.print("{}", x);
                out.print("{}", (m % 4 == 3 || m + 1 == n) ? '\n' : ' ');
            }
        }
}

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open Plot3D file", path));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::int32_t int_at(const std::string& bytes, size_t offset) {
    std::int32_t v = 0;
    if (offset + 4 <= bytes.size()) std::memcpy(&v, bytes.data() + offset, 4);
    return v;
}

bool looks_ascii(const std::string& bytes) {
    if (bytes.size() < 4) return false;
    for (int c = 0; c < 4; ++c) {
        const unsigned char ch = bytes[c];
        if (!(std::isdigit(ch) || std::isspace(ch))) return false;
    }
    return true;
}

// Header (block count and dims) and where the coordinates start, for binary encodings.
struct BinaryLayout {
    std::vector<Dims> dims;
    size_t data = 0;  // offset of the first coordinate record's payload
    Id points = 0;
};

BinaryLayout binary_layout(const std::string& bytes, bool fortran, const std::string& path) {
    BinaryLayout l;
    const size_t head = fortran ? 4 : 0;
    const std::int32_t nb = int_at(bytes, head);
    if (nb <= 0 || bytes.size() < head + 4 + size_t(nb) * 12)
        throw InputError(
            fmt::format("{}: not a Plot3D multi-block grid (block count {})", path, nb));
    const size_t dims_at = fortran ? 16 : 4;
    for (int b = 0; b < nb; ++b) {
        Dims d{int_at(bytes, dims_at + 12 * b), int_at(bytes, dims_at + 12 * b + 4),
               int_at(bytes, dims_at + 12 * b + 8)};
        if (d.ni < 2 || d.nj < 2 || d.nk < 2)
            throw InputError(fmt::format("{}: block {} has dims {} {} {}; a 3D grid needs >= 2",
                                         path, b + 1, d.ni, d.nj, d.nk));
        // Single-precision coordinates take 12 bytes a point: the file must hold them.
        if (double(l.points) + double(d.ni) * d.nj * d.nk > double(bytes.size()) / 12)
            throw InputError(
                fmt::format("{}: block {} has dims {} {} {}: more coordinates than the file's {} "
                            "bytes can hold",
                            path, b + 1, d.ni, d.nj, d.nk, bytes.size()));
        l.points += d.count();
        l.dims.push_back(d);
    }
    l.data = dims_at + 12 * size_t(nb) + (fortran ? 8 : 0);
    return l;
}

bool is_fortran(const std::string& bytes) {
    const std::int32_t nb = int_at(bytes, 4);
    return int_at(bytes, 0) == 4 && int_at(bytes, 8) == 4 && nb > 0 &&
           std::int64_t(int_at(bytes, 12)) == 12 * std::int64_t(nb);
}

// The patches of a neutral map file's boundary entries (WALL -> "wall", FARFIELD ->
// "farfield", any other type as written), whole block faces only.
void patches_from_map(BlockGrid& grid, const std::string& file) {
    const NeutralMap map = read_neutral_map(file);
    if (map.dims.size() != grid.blocks.size())
        throw InputError(fmt::format("{}: lists {} blocks, the grid has {}", file, map.dims.size(),
                                     grid.blocks.size()));
    for (size_t b = 0; b < map.dims.size(); ++b) {
        const Dims& d = grid.blocks[b].nodes;
        if (map.dims[b] != std::array<int, 3>{d.ni, d.nj, d.nk})
            throw InputError(fmt::format("{}: block {} is {} x {} x {}, the grid's {} x {} x {}",
                                         file, b + 1, map.dims[b][0], map.dims[b][1],
                                         map.dims[b][2], d.ni, d.nj, d.nk));
    }
    for (const NmfBoundary& e : map.boundaries) {
        const NmfFaceRange& r = e.range;
        const std::array<int, 3>& d = map.dims[size_t(r.block - 1)];
        const std::array<int, 3> far =
            nmf_face_node(d, r.face, std::max(r.s1, r.e1), std::max(r.s2, r.e2));
        const std::array<int, 3> near =
            nmf_face_node(d, r.face, std::min(r.s1, r.e1), std::min(r.s2, r.e2));
        const int normal = nmf_face_to_block_face(r.face) / 2;
        for (int a = 0; a < 3; ++a)
            if (a != normal && (near[a] != 0 || far[a] != d[a] - 1))
                throw InputError(
                    fmt::format("{}: '{}' on block {} face {} covers part of the face; only whole "
                                "faces are read",
                                file, e.type, r.block, r.face));
        grid.blocks[size_t(r.block - 1)].face_patch[nmf_face_to_block_face(r.face)] =
            e.type == "WALL"       ? "wall"
            : e.type == "FARFIELD" ? "farfield"
                                   : e.type;
    }
}

}  // namespace

std::string plot3d_patch_file(const std::string& path) {
    return path + ".patches.json";
}

std::string plot3d_map_file(const std::string& path) {
    return std::filesystem::path(path).replace_extension(".nmf").string();
}

void write_plot3d(const BlockGrid& grid, const std::string& path, const Plot3dFormat& format) {
    {
        const bool text = format.encoding == Plot3dEncoding::ascii;
        FileSink out(path, !text);
        const bool fortran = format.encoding == Plot3dEncoding::fortran;
        if (text)
            write_ascii(grid, out, format.single_precision);
        else if (format.single_precision)
            write_binary<float>(grid, out, fortran);
        else
            write_binary<double>(grid, out, fortran);
        out.close();
    }
    json side = {{"format", "hexmesh-plot3d-patches"}, {"version", 1}, {"blocks", json::array()}};
    for (const Block& b : grid.blocks)
        side["blocks"].push_back({{"name", b.name},
                                  {"dims", {b.nodes.ni, b.nodes.nj, b.nodes.nk}},
                                  {"face_patch", b.face_patch}});
    FileSink out(plot3d_patch_file(path), false);
    out.print("{}\n", side.dump(1));
    out.close();
    write_neutral_map(neutral_map(grid), plot3d_map_file(path));
}

static Plot3dFormat detect_format(const std::string& bytes, const std::string& path) {
    Plot3dFormat f;
    if (looks_ascii(bytes)) {
        f.encoding = Plot3dEncoding::ascii;
        return f;
    }
    f.encoding = is_fortran(bytes) ? Plot3dEncoding::fortran : Plot3dEncoding::c_binary;
    const bool fortran = f.encoding == Plot3dEncoding::fortran;
    const BinaryLayout l = binary_layout(bytes, fortran, path);
    // After the first block's opening marker: every block's closing marker and the others'
    // opening markers.
    const size_t markers = fortran ? 4 * (2 * l.dims.size() - 1) : 0;
    const size_t payload = bytes.size() - std::min(bytes.size(), l.data + markers);
    if (payload == size_t(3 * l.points) * 4)
        f.single_precision = true;
    else if (payload != size_t(3 * l.points) * 8)
        throw InputError(
            fmt::format("{}: {} bytes of coordinates for {} points: neither single "
                        "nor double precision",
                        path, payload, l.points));
    return f;
}

Plot3dFormat detect_plot3d_format(const std::string& path) {
    return detect_format(read_all(path), path);
}

namespace {

// The coordinates of an ASCII file: `dims` of each block and per block x..., y..., z...
void read_ascii_coordinates(const std::string& bytes, const std::string& path,
                            std::vector<Dims>& dims, std::vector<double>& coords) {
    const char* p = bytes.c_str();
    char* end = nullptr;
    auto next = [&](const char* what) {
        const double v = std::strtod(p, &end);
        if (end == p)
            throw InputError(
                fmt::format("{}: expected {} at byte {}", path, what, p - bytes.c_str()));
        p = end;
        return v;
    };
    // Counts are checked against what the file can hold before anything is sized by them:
    // a number takes at least 2 characters.
    const auto count = [&](const char* what, double lo, double hi) {
        const double v = next(what);
        if (!(v >= lo && v <= hi) || v != std::floor(v))
            throw InputError(fmt::format("{}: {} is {}; expected a whole number in [{}, {}]", path,
                                         what, v, lo, hi));
        return Id(v);
    };
    const double room = double(bytes.size()) / 2;
    const Id nb = count("the block count", 1, room / 3);
    Id total = 0;
    for (Id b = 0; b < nb; ++b) {
        Dims d{int(count("ni", 2, room)), int(count("nj", 2, room)), int(count("nk", 2, room))};
        if (double(d.ni) * d.nj * d.nk * 3 > room)
            throw InputError(
                fmt::format("{}: block {} has dims {} {} {}: more coordinates than the file's {} "
                            "bytes can hold",
                            path, b + 1, d.ni, d.nj, d.nk, bytes.size()));
        total += d.count();
        dims.push_back(d);
    }
    if (double(total) * 3 > room)
        throw InputError(
            fmt::format("{}: {} points: more coordinates than the file's {} bytes can hold", path,
                        total, bytes.size()));
    coords.resize(3 * total);
    for (double& v : coords) {
        v = next("a coordinate");
        if (!std::isfinite(v))
            throw InputError(
                fmt::format("{}: a coordinate is {} at byte {}", path, v, p - bytes.c_str()));
    }
    while (*p && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (*p)
        throw InputError(
            fmt::format("{}: more data after the {} coordinates the header announces (byte {})",
                        path, coords.size(), p - bytes.c_str()));
}

// The coordinates of a binary file (C or Fortran records, single or double precision), as
// read_ascii_coordinates gives them.
void read_binary_coordinates(const std::string& bytes, const std::string& path,
                             const Plot3dFormat& format, std::vector<Dims>& dims,
                             std::vector<double>& coords) {
    const bool fortran = format.encoding == Plot3dEncoding::fortran;
    const BinaryLayout l = binary_layout(bytes, fortran, path);
    dims = l.dims;
    coords.resize(3 * l.points);
    size_t at = l.data, m = 0;
    const size_t real = format.single_precision ? 4 : 8;
    for (const Dims& d : dims) {
        const size_t n = 3 * size_t(d.count());
        if (at + n * real > bytes.size()) throw InputError(fmt::format("{}: truncated", path));
        for (size_t v = 0; v < n; ++v, at += real) {
            if (real == 8)
                std::memcpy(&coords[m++], bytes.data() + at, 8);
            else {
                float x;
                std::memcpy(&x, bytes.data() + at, 4);
                coords[m++] = x;
            }
        }
        at += fortran ? 8 : 0;
    }
}

// The patch file beside the grid (null when there is none), listing `blocks` blocks.
json read_patch_side(const std::string& path, size_t blocks) {
    std::error_code ec;
    json side;
    if (std::filesystem::exists(plot3d_patch_file(path), ec)) {
        std::ifstream in(plot3d_patch_file(path));
        try {
            side = json::parse(in);
        } catch (const json::exception& e) {
            throw InputError(
                fmt::format("{}: malformed patch file: {}", plot3d_patch_file(path), e.what()));
        }
        if (!side.contains("blocks") || side["blocks"].size() != blocks)
            throw InputError(fmt::format("{}: lists a different number of blocks than {}",
                                         plot3d_patch_file(path), path));
    }
    return side;
}

// The blocks of those coordinates, nodes of exactly equal coordinates merged, named and
// patched by `side` when it is not null.
BlockGrid blocks_of(const std::vector<Dims>& dims, const std::vector<double>& coords,
                    const json& side, const std::string& path) {
    BlockGrid grid;
    std::unordered_map<std::string, Id> ids;  // exact coordinates (24 bytes) -> node
    size_t m = 0;
    for (size_t b = 0; b < dims.size(); ++b) {
        Block block;
        block.name = fmt::format("block{}", b);
        block.nodes = dims[b];
        const Id n = dims[b].count();
        block.node_ids.resize(n);
        for (Id v = 0; v < n; ++v) {
            const double x[3] = {coords[m + v], coords[m + n + v], coords[m + 2 * n + v]};
            auto [it, inserted] = ids.emplace(
                std::string(reinterpret_cast<const char*>(x), sizeof x), Id(grid.points.size()));
            if (inserted) grid.points.emplace_back(x[0], x[1], x[2]);
            block.node_ids[v] = it->second;
        }
        m += 3 * n;
        if (!side.is_null()) {
            const json& entry = side["blocks"][b];
            try {
                block.name = entry.at("name").get<std::string>();
                block.face_patch = entry.at("face_patch").get<std::array<std::string, 6>>();
            } catch (const json::exception& e) {
                throw InputError(
                    fmt::format("{}: blocks[{}]: {}", plot3d_patch_file(path), b, e.what()));
            }
        }
        grid.blocks.push_back(std::move(block));
    }
    grid.kinds.assign(grid.points.size(), VertexKind::interior);
    return grid;
}

}  // namespace

BlockGrid read_plot3d(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such Plot3D file", path));
    const std::string bytes = read_all(path);
    const Plot3dFormat format = detect_format(bytes, path);
    std::vector<Dims> dims;
    std::vector<double> coords;  // per block: x..., y..., z...
    if (format.encoding == Plot3dEncoding::ascii)
        read_ascii_coordinates(bytes, path, dims, coords);
    else
        read_binary_coordinates(bytes, path, format, dims, coords);
    const json side = read_patch_side(path, dims.size());
    BlockGrid grid = blocks_of(dims, coords, side, path);
    if (side.is_null() && std::filesystem::exists(plot3d_map_file(path), ec))
        patches_from_map(grid, plot3d_map_file(path));
    return grid;
}

}  // namespace hexmesh

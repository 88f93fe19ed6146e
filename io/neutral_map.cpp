#include "io/neutral_map.h"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "io/file_sink.h"
#include "io/input_error.h"

namespace hexmesh {
namespace {

// The index axis held constant on a map face, and its first and second directions.
struct FaceAxes {
    int normal, first, second;
    bool max_side;
};

FaceAxes face_axes(int face) {
    switch (face) {
        case 1:
            return {2, 0, 1, false};
        case 2:
            return {2, 0, 1, true};
        case 3:
            return {0, 1, 2, false};
        case 4:
            return {0, 1, 2, true};
        case 5:
            return {1, 2, 0, false};
        default:
            return {1, 2, 0, true};
    }
}

std::string type_of(const std::string& patch) {
    if (patch == "wall") return "WALL";
    if (patch == "farfield") return "FARFIELD";
    return patch;
}

}  // namespace

int nmf_face_to_block_face(int face) {
    const FaceAxes a = face_axes(face);
    return 2 * a.normal + (a.max_side ? 1 : 0);
}

int block_face_to_nmf_face(int block_face) {
    for (int f = 1; f <= 6; ++f)
        if (nmf_face_to_block_face(f) == block_face) return f;
    return 0;
}

std::array<int, 3> nmf_face_node(const std::array<int, 3>& dims, int face, int u, int v) {
    const FaceAxes a = face_axes(face);
    std::array<int, 3> ijk{};
    ijk[a.normal] = a.max_side ? dims[a.normal] - 1 : 0;
    ijk[a.first] = u - 1;
    ijk[a.second] = v - 1;
    return ijk;
}

NeutralMap neutral_map(const BlockGrid& grid) {
    NeutralMap map;
    for (const Block& b : grid.blocks) map.dims.push_back({b.nodes.ni, b.nodes.nj, b.nodes.nk});
    const auto whole = [&](int b, int face) {
        const FaceAxes a = face_axes(face);
        return NmfFaceRange{b + 1, face, 1, map.dims[b][a.first], 1, map.dims[b][a.second]};
    };
    const auto node = [&](int b, int face, int u, int v) {
        const std::array<int, 3> ijk = nmf_face_node(map.dims[b], face, u, v);
        return grid.blocks[b].node(ijk[0], ijk[1], ijk[2]);
    };
    // Unpatched faces by their sorted corner nodes: two such faces with the same corners meet.
    std::map<std::array<Id, 4>, std::vector<std::pair<int, int>>> by_corners;
    for (int b = 0; b < int(grid.blocks.size()); ++b)
        for (int face = 1; face <= 6; ++face) {
            const std::string& patch = grid.blocks[b].face_patch[nmf_face_to_block_face(face)];
            const NmfFaceRange r = whole(b, face);
            if (!patch.empty()) {
                map.boundaries.push_back({type_of(patch), r});
                continue;
            }
            std::array<Id, 4> corners = {node(b, face, 1, 1), node(b, face, r.e1, 1),
                                         node(b, face, 1, r.e2), node(b, face, r.e1, r.e2)};
            std::sort(corners.begin(), corners.end());
            by_corners[corners].push_back({b, face});
        }
    for (const auto& [corners, faces] : by_corners) {
        if (faces.size() != 2) continue;  // a face matched by none: no interface to state
        const auto [a, fa] = faces[0];
        const auto [b, fb] = faces[1];
        NmfInterface link{whole(a, fa), whole(b, fb), false};
        // Where the first face's origin and its two unit steps land on the second face.
        std::unordered_map<Id, std::array<int, 2>> on_b;
        for (int u = 1; u <= link.second.e1; ++u)
            for (int v = 1; v <= link.second.e2; ++v) on_b[node(b, fb, u, v)] = {u, v};
        const std::array<int, 2> o = on_b.at(node(a, fa, 1, 1));
        const std::array<int, 2> du = on_b.at(node(a, fa, 2, 1)), dv = on_b.at(node(a, fa, 1, 2));
        const int n1 = link.first.e1 - 1, n2 = link.first.e2 - 1;  // steps along the first face
        link.swap = du[0] == o[0];  // the first face's first direction runs along b's second
        NmfFaceRange& s = link.second;
        if (!link.swap) {
            s.s1 = o[0], s.e1 = o[0] + n1 * (du[0] - o[0]);
            s.s2 = o[1], s.e2 = o[1] + n2 * (dv[1] - o[1]);
        } else {
            s.s1 = o[0], s.e1 = o[0] + n2 * (dv[0] - o[0]);
            s.s2 = o[1], s.e2 = o[1] + n1 * (du[1] - o[1]);
        }
        map.interfaces.push_back(link);
    }
    return map;
}

void write_neutral_map(const NeutralMap& map, const std::string& path) {
    FileSink out(path, false);
    const std::string rule(83, '=');
    out.print(
        "# ===== Neutral Map File written by hexmesh {}\n# Block#   IDIM   JDIM   KDIM\n# "
        "{}\n{:8}\n",
        std::string(55, '='), std::string(81, '-'), map.dims.size());
    for (size_t b = 0; b < map.dims.size(); ++b)
        out.print("{:8} {:6} {:6} {:6}\n", b + 1, map.dims[b][0], map.dims[b][1], map.dims[b][2]);
    out.print(
        "# {}\n# Type           B1  F1     S1   E1     S2   E2     B2  F2     S1   E1     S2   E2  "
        " Swap\n# {}\n",
        std::string(81, '='), std::string(81, '-'));
    const auto range = [](const NmfFaceRange& r) {
        return fmt::format("{:4} {:3} {:6} {:4} {:6} {:4}", r.block, r.face, r.s1, r.e1, r.s2,
                           r.e2);
    };
    for (const NmfBoundary& b : map.boundaries)
        out.print("{:<14} {}\n", "'" + b.type + "'", range(b.range));
    for (const NmfInterface& i : map.interfaces)
        out.print("{:<14} {} {} {}\n", "'ONE_TO_ONE'", range(i.first), range(i.second),
                  i.swap ? "TRUE" : "FALSE");
    out.close();
}

namespace {

// One line of a map file, split into words at blanks (its comment cut off), and what its
// errors name.
struct MapLine {
    const std::string& path;
    int number = 0;
    std::vector<std::string> w;

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(fmt::format("{}: line {}: {}", path, number, what));
    }

    // Word k as an integer in [low, high]; `what` names it.
    int integer(size_t k, long low, long high, const char* what) const {
        char* end = nullptr;
        const long v = std::strtol(w[k].c_str(), &end, 10);
        if (*end || end == w[k].c_str() || v < low || v > high)
            fail(fmt::format("{} is '{}'; expected an integer in [{}, {}]", what, w[k], low, high));
        return int(v);
    }
};

// The face range of words k to k + 5: block, face, S1 E1 S2 E2 within the block's face.
NmfFaceRange face_range(const MapLine& l, size_t k, const NeutralMap& map, size_t blocks) {
    NmfFaceRange r;
    r.block = l.integer(k, 1, long(blocks), "the block");
    r.face = l.integer(k + 1, 1, 6, "the face");
    const FaceAxes a = face_axes(r.face);
    const std::array<int, 3>& d = map.dims[size_t(r.block - 1)];
    r.s1 = l.integer(k + 2, 1, d[a.first], "S1");
    r.e1 = l.integer(k + 3, 1, d[a.first], "E1");
    r.s2 = l.integer(k + 4, 1, d[a.second], "S2");
    r.e2 = l.integer(k + 5, 1, d[a.second], "E2");
    return r;
}

// A ONE_TO_ONE line: two face ranges of the same size (once swapped, if Swap) and Swap.
NmfInterface read_interface(const MapLine& l, const NeutralMap& map, size_t blocks) {
    const std::vector<std::string>& w = l.w;
    if (w.size() != 14) l.fail("a ONE_TO_ONE line has 14 fields: type, two face ranges and Swap");
    NmfInterface link{face_range(l, 1, map, blocks), face_range(l, 7, map, blocks), false};
    std::string swap = w[13];
    for (char& c : swap) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (swap != "TRUE" && swap != "FALSE")
        l.fail(fmt::format("Swap is '{}'; expected TRUE or FALSE", w[13]));
    link.swap = swap == "TRUE";
    const int n1 = std::abs(link.first.e1 - link.first.s1),
              n2 = std::abs(link.first.e2 - link.first.s2);
    const int m1 = std::abs(link.second.e1 - link.second.s1),
              m2 = std::abs(link.second.e2 - link.second.s2);
    if ((link.swap ? std::array<int, 2>{m2, m1} : std::array<int, 2>{m1, m2}) !=
        std::array<int, 2>{n1, n2})
        l.fail("the two faces of a ONE_TO_ONE interface have different sizes");
    return link;
}

}  // namespace

NeutralMap read_neutral_map(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(fmt::format("{}: cannot open the neutral map file", path));
    NeutralMap map;
    std::string text;
    MapLine l{path, 0, {}};
    size_t blocks = 0;
    bool have_count = false;
    while (std::getline(in, text)) {
        ++l.number;
        text = text.substr(0, text.find('#'));
        std::istringstream words(text);
        std::vector<std::string>& w = l.w;
        w.clear();
        for (std::string s; words >> s;) w.push_back(s);
        if (w.empty()) continue;
        if (!have_count) {
            if (w.size() != 1) l.fail("expected the number of blocks alone on its line");
            blocks = size_t(l.integer(0, 1, 1000000, "the number of blocks"));
            have_count = true;
            continue;
        }
        if (map.dims.size() < blocks) {
            if (w.size() != 4) l.fail("expected a block line: number IDIM JDIM KDIM");
            if (l.integer(0, 1, long(blocks), "the block number") != int(map.dims.size()) + 1)
                l.fail(fmt::format("expected block {} next", map.dims.size() + 1));
            map.dims.push_back({l.integer(1, 2, 1 << 30, "IDIM"), l.integer(2, 2, 1 << 30, "JDIM"),
                                l.integer(3, 2, 1 << 30, "KDIM")});
            continue;
        }
        std::string type = w[0];
        if (type.size() >= 2 && type.front() == '\'' && type.back() == '\'')
            type = type.substr(1, type.size() - 2);
        std::string upper = type;
        for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
        if (upper == "ONE_TO_ONE") {
            map.interfaces.push_back(read_interface(l, map, blocks));
        } else {
            if (w.size() != 7)
                l.fail(fmt::format("a boundary line ('{}') has 7 fields: type and one face range",
                                   type));
            map.boundaries.push_back({type, face_range(l, 1, map, blocks)});
        }
    }
    if (!have_count || map.dims.size() < blocks)
        throw InputError(fmt::format("{}: ends before its {} block sizes", path, blocks));
    return map;
}

}  // namespace hexmesh

// The core blocks of an O-H grid: one box, or the axial core (column, ring pieces, frame) laid
// out over the rings around its axis.
#include "volume/core_layout.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "volume/cube_sphere.h"

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;

// tan(pi/4 (2 m/n - 1)): the equiangular coordinate of lattice index m.
double equiangular_index(int m, int n) {
    return std::tan(pi / 4 * (2.0 * m / n - 1));
}

}  // namespace

CoreLayout one_block_core(int n) {
    CoreLayout core;
    Block block{"core", {n + 1, n + 1, n + 1}, {}, {}};
    block.node_ids.resize(block.nodes.count());
    std::iota(block.node_ids.begin(), block.node_ids.end(), Id(0));
    core.t.resize(block.nodes.count());
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                core.t[block.nodes.flat(i, j, k)] = equiangular({i, j, k}, n);
    core.blocks.push_back(std::move(block));
    for (int side = 0; side < 6; ++side) {
        const CubePatch& patch = cube_patches[side];
        core.wall_faces.push_back({0, BlockFace(2 * patch.axis + patch.max_side), side});
    }
    std::sort(core.wall_faces.begin(), core.wall_faces.end(),
              [](const auto& a, const auto& b) { return a.face < b.face; });
    return core;
}

double axial_frame_edge(int n, int frame) {
    return frame > 0 ? equiangular_index(n - frame, n) : 1.0;
}

namespace {

using Vec2 = Eigen::Vector2d;

// One piece of the axial core's cross-section: nodes (i, j), i fastest, at in-plane cube
// coordinates (t_b, t_c), with (i, j) counter-clockwise so (i, j, axis) is right-handed.
struct SectionPiece {
    std::string name;
    int ni = 0, nj = 0;  // node counts
    std::vector<Vec2> t;
};

// The cross-section of the axial core (see axial_core): column, rings, frame.
std::vector<SectionPiece> cross_section(int n, int frame, const AxialRings& rings, int b, int c) {
    const int m = n - 2 * frame, r = rings.cells();
    const double outer = rings.radius.back();
    std::vector<SectionPiece> pieces;
    SectionPiece column{"column", m + 1, m + 1, {}};
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i)
            column.t.push_back(rings.column() *
                               Vec2(equiangular_index(i, m), equiangular_index(j, m)));
    pieces.push_back(std::move(column));
    // Piece q reaches out along d = +b, +c, -b, -c; `along` (the axis x d) turns around it.
    const Vec2 out[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const int side[4] = {2 * b + 1, 2 * c + 1, 2 * b, 2 * c};
    auto along = [&](int q) { return Vec2(-out[q].y(), out[q].x()); };
    for (int q = 0; q < 4; ++q) {
        SectionPiece ring{std::string("ring_") + cube_patches[side[q]].side, r + 1, m + 1, {}};
        for (int j = 0; j <= m; ++j)
            for (int s = 0; s <= r; ++s) {
                const double angle = pi / 4 * (2.0 * j / m - 1), round = rings.roundness[s];
                const Vec2 square = out[q] + equiangular_index(j, m) * along(q);
                const Vec2 circle = std::cos(angle) * out[q] + std::sin(angle) * along(q);
                ring.t.push_back(rings.radius[s] * ((1 - round) * square + round * circle));
            }
        pieces.push_back(std::move(ring));
    }
    if (frame == 0) return pieces;
    // The frame: its sides run from the rings' last square to the cube's faces, radially at
    // the equiangular coordinates of the cube's lattice; its corners are that lattice.
    for (int q = 0; q < 4; ++q) {
        SectionPiece f{std::string("frame_") + cube_patches[side[q]].side, frame + 1, m + 1, {}};
        const double edge = equiangular_index(n, n);
        for (int j = 0; j <= m; ++j)
            for (int i = 0; i <= frame; ++i) {
                const double radial = equiangular_index(n - frame + i, n);
                const double blend = (radial - outer) / (edge - outer);
                const Vec2 inner = outer * (out[q] + equiangular_index(j, m) * along(q));
                const Vec2 face = edge * out[q] + equiangular_index(frame + j, n) * along(q);
                f.t.push_back((1 - blend) * inner + blend * face);
            }
        pieces.push_back(std::move(f));
    }
    for (int q = 0; q < 4; ++q) {
        const int next = (q + 1) % 4;
        SectionPiece corner{std::string("frame_") + cube_patches[side[q]].side + "_" +
                                cube_patches[side[next]].side,
                            frame + 1,
                            frame + 1,
                            {}};
        for (int j = 0; j <= frame; ++j)
            for (int i = 0; i <= frame; ++i)
                corner.t.push_back(equiangular_index(n - frame + i, n) * out[q] +
                                   equiangular_index(n - frame + j, n) * out[next]);
        pieces.push_back(std::move(corner));
    }
    return pieces;
}

// Numbers the pieces' nodes once each: nodes within 1e-8 of each other (a shared edge
// computed from either side) get one id. ids[piece][node].
std::vector<std::vector<Id>> number_section(const std::vector<SectionPiece>& pieces,
                                            std::vector<Vec2>& points) {
    constexpr double quantum = 1e-8;
    std::map<std::pair<long long, long long>, Id> seen;
    std::vector<std::vector<Id>> ids;
    for (const SectionPiece& piece : pieces) {
        std::vector<Id>& piece_ids = ids.emplace_back();
        for (const Vec2& t : piece.t) {
            const long long x = std::llround(t.x() / quantum), y = std::llround(t.y() / quantum);
            Id id = -1;
            for (long long dx = -1; dx <= 1 && id < 0; ++dx)
                for (long long dy = -1; dy <= 1 && id < 0; ++dy)
                    if (auto it = seen.find({x + dx, y + dy}); it != seen.end()) id = it->second;
            if (id < 0) {
                id = Id(points.size());
                points.push_back(t);
                seen[{x, y}] = id;
            }
            piece_ids.push_back(id);
        }
    }
    return ids;
}

}  // namespace

CoreLayout axial_core(int n, int frame, const AxialRings& rings) {
    const int a = rings.axis, b = (a + 1) % 3, c = (a + 2) % 3, r = rings.cells();
    if (r < 1 || int(rings.roundness.size()) != r + 1)
        throw std::invalid_argument("axial rings: radius and roundness need cells + 1 values");
    if (frame < 0 || n - 2 * frame < 1)
        throw std::invalid_argument("axial core: the frame leaves no cells for the rings");
    if (std::abs(rings.radius.back() - axial_frame_edge(n, frame)) > 1e-12)
        throw std::invalid_argument("axial rings: the last ring is not the frame's inner edge");
    const std::vector<SectionPiece> pieces = cross_section(n, frame, rings, b, c);
    std::vector<Vec2> section;
    const std::vector<std::vector<Id>> ids = number_section(pieces, section);
    const Id per_layer = Id(section.size());

    CoreLayout core;
    core.t.resize(per_layer * (n + 1));
    for (int k = 0; k <= n; ++k)
        for (Id id = 0; id < per_layer; ++id) {
            Vec3& t = core.t[id + per_layer * k];
            t[a] = equiangular_index(k, n);
            t[b] = section[id].x();
            t[c] = section[id].y();
        }
    for (size_t p = 0; p < pieces.size(); ++p) {
        const SectionPiece& piece = pieces[p];
        Block block{"core_" + piece.name, {piece.ni, piece.nj, n + 1}, {}, {}};
        block.node_ids.resize(block.nodes.count());
        for (int k = 0; k <= n; ++k)
            for (int j = 0; j < piece.nj; ++j)
                for (int i = 0; i < piece.ni; ++i)
                    block.node_ids[block.nodes.flat(i, j, k)] =
                        ids[p][i + piece.ni * j] + per_layer * k;
        // Faces on the cube's sides: every node of the piece's edge at |t_b| or |t_c| = 1.
        for (const BlockFace face : {imin, imax, jmin, jmax}) {
            for (const int d : {b, c}) {
                const Id first =
                    block.node(face == imax ? piece.ni - 1 : 0, face == jmax ? piece.nj - 1 : 0, 0);
                const double sign = core.t[first][d] > 0 ? 1.0 : -1.0;
                bool on_side = true;
                const int count = face < jmin ? piece.nj : piece.ni;
                for (int e = 0; e < count && on_side; ++e) {
                    const int i = face < jmin ? (face == imax ? piece.ni - 1 : 0) : e;
                    const int j = face < jmin ? e : (face == jmax ? piece.nj - 1 : 0);
                    on_side = sign * core.t[block.node(i, j, 0)][d] > 1 - 1e-9;
                }
                if (on_side) core.wall_faces.push_back({int(p), face, 2 * d + (sign > 0)});
            }
        }
        core.wall_faces.push_back({int(p), kmin, 2 * a});
        core.wall_faces.push_back({int(p), kmax, 2 * a + 1});
        core.blocks.push_back(std::move(block));
    }
    return core;
}

}  // namespace hexmesh

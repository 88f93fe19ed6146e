// measure_quality of a block grid in one pass, block by block and slab by slab: faces inside a
// block meet their structured neighbour, faces on block boundaries wait for the cell across.
//
// An internal face is owned by the lower cell and its measures use the owner's point order,
// the cell above seeing the negated area vector; a cell on a block boundary computes its
// boundary faces from its own points (the same face to rounding).
#include "hexmesh/quality/block_quality.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/core/bytes.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/face_geometry.h"
#include "hexmesh/quality/quality_tally.h"

namespace hexmesh {
namespace {

using detail::add_cell;
using detail::add_internal_face;
using detail::CellGeometry;
using detail::CellStats;
using detail::face_of;
using detail::FaceGeometry;
using detail::FaceStats;
using detail::make_report;

// For an imin / jmin / kmin face f: the local nodes of this cell that the cell below lists
// on its face f + 1, in its order (its node n is our node n with the axis bit flipped).
constexpr std::array<std::array<int, 4>, 6> seen_from_lower = {{
    {0, 3, 7, 4},  // below's imax face {1, 2, 6, 5}, x flipped
    {},
    {1, 0, 4, 5},  // below's jmax face {2, 3, 7, 6}, y flipped
    {},
    {0, 1, 2, 3},  // below's kmax face {4, 5, 6, 7}, z flipped
    {},
}};

// One k-slab of a block as the block pass keeps it: per cell (i + ni j) its centre, volume
// and kmax face as its owner sees it (the kmin face of the cell above).
struct Slab {
    std::vector<Vec3> centre;
    std::vector<double> volume;
    std::vector<FaceGeometry> kmax;
    void resize(size_t n) {
        centre.resize(n);
        volume.resize(n);
        kmax.resize(n);
    }
};

// A face on a block boundary as one of its cells sees it, waiting for the cell across (which
// may be in a block not yet added): its points in that cell's hex_faces order, and the cell.
struct OpenFace {
    Id cell = 0;
    std::array<Vec3, 4> p;
    Vec3 centre;
    double volume = 0;
};

using FaceKey = std::array<Id, 4>;  // the face's global node ids, sorted

// What one range of slabs of a block yields: its face measures and its open faces.
struct BlockFaces {
    FaceStats stats;
    std::vector<std::pair<FaceKey, OpenFace>> open;

    void join(BlockFaces& o) {
        stats.join(o.stats);
        open.insert(open.end(), std::make_move_iterator(o.open.begin()),
                    std::make_move_iterator(o.open.end()));
    }
};

using OpenFaces = std::unordered_map<FaceKey, OpenFace, ArrayHash<Id, 4>>;
using MatchedFaces = std::unordered_map<FaceKey, std::pair<Id, Id>, ArrayHash<Id, 4>>;  // 2 cells

// The block being added: its cell counts, its points, the global id of its first cell, and
// its node ids in the whole grid (`ids`, when its grid numbers its points on its own).
struct BlockPass {
    const Block& block;
    const std::vector<Vec3>& points;
    Dims d;
    size_t plane;  // cells per k-slab
    Id first;      // of the whole block this one is part of (CellNumbering)
    std::array<int, 3> offset;
    Dims whole;
    const std::vector<Id>* ids;

    Id global(Id v) const { return ids ? (*ids)[size_t(v)] : v; }
    Id cell(int i, int j, int k) const {
        return first + whole.flat(i + offset[0], j + offset[1], k + offset[2]);
    }
};

// The six faces of a cell with corner points p as it sees them: on the block boundary or
// owned by it, from its own points; else the owner's (imax of the cell to the left, jmax of
// the one in the row below, kmax of the one in the slab below, or, for a slab computed
// without the one below, its points in the owner's order), area negated.
std::array<FaceGeometry, 6> cell_faces(const std::array<Vec3, 8>& p,
                                       const std::array<bool, 6>& inside, const FaceGeometry& imax,
                                       const FaceGeometry& jmax, const Slab* below, size_t at) {
    std::array<FaceGeometry, 6> faces;
    for (int f = 0; f < 6; ++f) {
        if (!inside[f] || f % 2 == 1) {  // on the boundary, or owned: own points
            faces[f] = detail::quad_geometry(face_of(p, hex_faces[f]));
        } else {  // the owner below computed it (or, for a slab computed
                  // without the one below, its points in the owner's order)
            faces[f] = f == 0   ? imax
                       : f == 2 ? jmax
                       : below  ? below->kmax[at]
                                : detail::quad_geometry(face_of(p, seen_from_lower[f]));
            faces[f].area = -faces[f].area;
        }
    }
    return faces;
}

// The measures of the internal faces between cell `at` of slab `out` and the cells below it
// along i, j and k (slab `below`), each face in its owner's order.
void add_faces_from_below(FaceStats& stats, const BlockPass& b, size_t at,
                          const std::array<Vec3, 8>& p, const std::array<bool, 6>& inside,
                          const std::array<FaceGeometry, 6>& faces, const CellGeometry& g,
                          const Slab& out, const Slab* below) {
    for (int f = 0; f < 6; f += 2) {
        if (!inside[f]) continue;
        const std::array<Vec3, 4> q = face_of(p, seen_from_lower[f]);
        FaceGeometry owner_face = faces[f];
        owner_face.area = -owner_face.area;
        const size_t lower = f == 0 ? at - 1 : f == 2 ? at - size_t(b.d.ni) : at;
        const Slab& s = f == 4 ? *below : out;
        add_internal_face(stats, q, owner_face, s.centre[lower], g.centre, s.volume[lower],
                          g.volume);
    }
}

// Cell c's faces on the block boundary, left open under their sorted global node ids.
void add_open_faces(std::vector<std::pair<FaceKey, OpenFace>>& open, const BlockPass& b, Id c,
                    const std::array<Id, 8>& nodes, const std::array<Vec3, 8>& p,
                    const std::array<bool, 6>& inside, const CellGeometry& g) {
    for (int f = 0; f < 6; ++f) {
        if (inside[f]) continue;
        FaceKey key;
        for (int n = 0; n < 4; ++n) key[n] = b.global(nodes[hex_faces[f][n]]);
        std::sort(key.begin(), key.end());
        open.push_back({key, {c, face_of(p, hex_faces[f]), g.centre, g.volume}});
    }
}

// Slab k into `out`; with `stats`, its cells' measures too, and with `below` (slab k - 1)
// the measures of every internal face whose upper cell is in slab k, and its open faces.
void measure_slab(const BlockPass& b, int k, Slab& out, const Slab* below, CellStats* stats,
                  BlockFaces* faces_acc) {
    const Dims& d = b.d;
    std::vector<FaceGeometry> jmax(size_t(d.ni));  // of the row below
    for (int j = 0; j < d.nj; ++j) {
        FaceGeometry imax;  // of the cell to the left
        for (int i = 0; i < d.ni; ++i) {
            const size_t at = size_t(i) + size_t(d.ni) * size_t(j);
            const std::array<Id, 8> nodes = cell_nodes(b.block, i, j, k);
            std::array<Vec3, 8> p;
            for (int n = 0; n < 8; ++n) p[n] = b.points[nodes[n]];
            const std::array<bool, 6> inside = {i > 0, i<d.ni - 1, j> 0, j<d.nj - 1, k> 0,
                                                k < d.nk - 1};
            const std::array<FaceGeometry, 6> faces =
                cell_faces(p, inside, imax, jmax[size_t(i)], below, at);
            const CellGeometry g = detail::cell_geometry(faces);
            out.centre[at] = g.centre;
            out.volume[at] = g.volume;
            out.kmax[at] = faces[5];
            imax = faces[1];
            jmax[size_t(i)] = faces[3];
            if (!stats) continue;
            const Id c = b.cell(i, j, k);
            add_cell(*stats, c, faces, g, p);
            // Faces: internal ones from below (i, j, k), then block-boundary ones.
            add_faces_from_below(faces_acc->stats, b, at, p, inside, faces, g, out, below);
            add_open_faces(faces_acc->open, b, c, nodes, p, inside, g);
        }
    }
}

// Every slab of the block: its cells' measures into slab_stats[k], its internal faces'
// measures and its open faces returned. Slab ranges run in parallel, each one computing the
// slab below its first for the faces in between.
BlockFaces measure_slabs(const BlockPass& b, std::vector<CellStats>& slab_stats) {
    const int grain = std::max(2, b.d.nk / 16);  // each range also computes the slab below it
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, b.d.nk, grain), BlockFaces{},
        [&](const tbb::blocked_range<int>& r, BlockFaces acc) {
            Slab below, current;
            below.resize(b.plane);
            current.resize(b.plane);
            if (r.begin() > 0) measure_slab(b, r.begin() - 1, below, nullptr, nullptr, nullptr);
            for (int k = r.begin(); k != r.end(); ++k) {
                measure_slab(b, k, current, k > 0 ? &below : nullptr, &slab_stats[size_t(k)], &acc);
                std::swap(below, current);
            }
            return acc;
        },
        [](BlockFaces x, BlockFaces y) {
            x.join(y);
            return x;
        },
        tbb::simple_partitioner{});  // ranges of at most `grain` slabs, whatever the load
}

// Pairs the block's open faces with those already open (from earlier blocks, or earlier in
// this one); the owner is the lower cell, its point order gives the face geometry. Throws
// std::invalid_argument when a face is already matched.
void pair_open_faces(std::vector<std::pair<FaceKey, OpenFace>>& faces, OpenFaces& open,
                     MatchedFaces& matched, FaceStats& per_face) {
    for (auto& [key, face] : faces) {
        if (const auto m = matched.find(key); m != matched.end()) {
            std::ostringstream msg;
            msg << "a face is shared by more than two cells (cells " << m->second.first << ", "
                << m->second.second << ", " << face.cell << "); the mesh is not a valid hex mesh";
            throw std::invalid_argument(msg.str());
        }
        const auto [it, inserted] = open.try_emplace(key, face);
        if (inserted) continue;
        const OpenFace& a = it->second.cell < face.cell ? it->second : face;
        const OpenFace& b = it->second.cell < face.cell ? face : it->second;
        add_internal_face(per_face, a.p, detail::quad_geometry(a.p), a.centre, b.centre, a.volume,
                          b.volume);
        matched.emplace(key, std::make_pair(a.cell, b.cell));
        open.erase(it);
    }
}

}  // namespace

struct BlockQuality::State {
    Id cells = 0;  // cells added so far: the global id of the next block's first cell
    CellStats per_cell;
    FaceStats per_face;
    OpenFaces open;
    MatchedFaces matched;
};

BlockQuality::BlockQuality() : state_(std::make_unique<State>()) {}
BlockQuality::~BlockQuality() = default;

// One block slab by slab (k), row by row (j), cell by cell (i): every face inside the block is
// computed once, by its owner (the lower cell: the one below along i, j or k), and reused by
// the cell above it; its face measures are taken as soon as both centres are known. Faces on
// the block's boundary are computed from the cell's own points and left open, to be paired
// by node ids with the cell across. The scaled-Jacobian sum is added slab by slab in order,
// so the result does not depend on how the slabs are split between threads.
void BlockQuality::add(const BlockGrid& grid, const Block& block, const std::vector<Id>* ids,
                       const CellNumbering& numbering) {
    State& st = *state_;
    const Dims d = block.cells();
    if (d.count() == 0) return;
    const BlockPass pass{block,
                         grid.points,
                         d,
                         size_t(d.ni) * size_t(d.nj),
                         numbering.first >= 0 ? numbering.first : st.cells,
                         numbering.offset,
                         numbering.whole.count() > 0 ? numbering.whole : d,
                         ids};
    std::vector<CellStats> slab_stats(size_t(d.nk));
    BlockFaces block_faces = measure_slabs(pass, slab_stats);
    st.per_face.join(block_faces.stats);
    for (const CellStats& s : slab_stats) st.per_cell.join(s);
    st.cells += d.count();
    pair_open_faces(block_faces.open, st.open, st.matched, st.per_face);
}

QualityReport BlockQuality::report() const {
    const State& st = *state_;
    if (st.cells == 0) return QualityReport{};
    FaceStats per_face = st.per_face;
    for (const auto& [key, face] : st.open)  // never paired: boundary faces
        per_face.add_skewness(
            detail::boundary_face_skewness(face.p, detail::quad_geometry(face.p), face.centre));
    return make_report(st.cells, st.per_cell, per_face);
}

namespace {

void put(ByteWriter& out, const RankedCell& r) {
    out.put(r.cell), out.put(r.scaled_jacobian), out.put(r.centre);
}
void get(ByteReader& in, RankedCell& r) {
    in.get(r.cell), in.get(r.scaled_jacobian), in.get(r.centre);
}

void put(ByteWriter& out, const CellStats& c) {
    out.put(c.min_sj), out.put(c.worst), out.put(c.worst_centre), out.put(c.sum_sj);
    out.put(c.max_aspect), out.put(c.min_volume), out.put(c.inverted_tets);
    out.put(c.inverted_cells), out.put(c.negative_pyramids), out.put(c.nonpositive_volumes);
    out.put(c.high_aspect);
    out.put(c.sj_histogram);
    out.put(c.lowest.size());
    for (const RankedCell& r : c.lowest) put(out, r);
}

void get(ByteReader& in, CellStats& c) {
    in.get(c.min_sj), in.get(c.worst), in.get(c.worst_centre), in.get(c.sum_sj);
    in.get(c.max_aspect), in.get(c.min_volume), in.get(c.inverted_tets);
    in.get(c.inverted_cells), in.get(c.negative_pyramids), in.get(c.nonpositive_volumes);
    in.get(c.high_aspect);
    in.get(c.sj_histogram);
    c.lowest.resize(in.next<size_t>());
    for (RankedCell& r : c.lowest) get(in, r);
}

void put(ByteWriter& out, const FaceStats& f) {
    out.put(f.min_ortho), out.put(f.max_skew), out.put(f.max_volume_ratio);
    out.put(f.over_90_deg), out.put(f.over_skew), out.put(f.non_orthogonality);
}

void get(ByteReader& in, FaceStats& f) {
    in.get(f.min_ortho), in.get(f.max_skew), in.get(f.max_volume_ratio);
    in.get(f.over_90_deg), in.get(f.over_skew), in.get(f.non_orthogonality);
}

}  // namespace

std::string BlockQuality::pack() const {
    const State& st = *state_;
    ByteWriter out;
    out.put(st.cells);
    put(out, st.per_cell);
    put(out, st.per_face);
    out.put(st.open.size());
    for (const auto& [key, face] : st.open) {
        out.put(key), out.put(face.cell), out.put(face.p), out.put(face.centre);
        out.put(face.volume);
    }
    return out.bytes();
}

void BlockQuality::merge(const std::string& packed) {
    State& st = *state_;
    ByteReader in(packed);
    st.cells += in.next<Id>();
    CellStats per_cell;
    get(in, per_cell);
    st.per_cell.join(per_cell);
    FaceStats per_face;
    get(in, per_face);
    st.per_face.join(per_face);
    std::vector<std::pair<FaceKey, OpenFace>> open(in.next<size_t>());
    for (auto& [key, face] : open) {
        in.get(key), in.get(face.cell), in.get(face.p), in.get(face.centre);
        in.get(face.volume);
    }
    pair_open_faces(open, st.open, st.matched, st.per_face);
}

QualityReport measure_quality(const BlockGrid& grid) {
    BlockQuality q;
    for (const Block& block : grid.blocks) q.add(grid, block);
    return q.report();
}

}  // namespace hexmesh

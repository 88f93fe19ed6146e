// Assembly of the functional over all elements: energy, gradient and block Hessian.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "untangle/block_matrix.h"
#include "untangle/problem.h"

namespace hexmesh::untangle {

// Element statistics in target units (det S = 1 for a perfect element).
struct ElementStats {
    double min_det = 0;
    Id inverted = 0;  // elements with det S <= 0
};

// Precomputes the element schedule and the Hessian's block pattern, so that every sum below
// is parallel yet deterministic (the same input gives the same bits whatever the number of
// threads). Elements are cut into chunks of consecutive elements; chunks are coloured so
// that no two chunks of one colour share a vertex. Colours run one after the other, the chunks of a
// colour in parallel, the elements of a chunk in order: few synchronizations, and neighbouring
// elements share the cache.
class Assembly {
  public:
    // Elements go in chunks of chunk_elements (fewer if the colouring needs it); a hex whose
    // corner tets a chunk boundary splits is assembled tet by tet.
    explicit Assembly(const Problem& problem, Id chunk_elements = 256);

    ElementStats stats(const std::vector<Vec3>& x) const;
    // Every sum below weighs each element by its target's volume (area), or each tet by a
    // unit target's when p.equal_weights.
    // F(x); +infinity when eps = 0 and an element is inverted.
    double energy(const std::vector<Vec3>& x, const EnergyParams& p) const;
    // F(x) and its gradient (#V vectors).
    double gradient(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g) const;
    // F(x), gradient and the PSD-projected Hessian in `h` (pattern from empty_hessian()).
    double hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                   BlockMatrix& h) const;
    // The Hessian's pattern with zero blocks (the pattern itself keeps no values).
    BlockMatrix empty_hessian() const;
    // F(x), gradient and only the diagonal blocks of the PSD Hessian (#V blocks).
    double diagonal_hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                            std::vector<Mat3>& diagonal) const;
    // out = H(x) v without storing H: element Hessians recomputed and applied one by one.
    void hessian_product(const std::vector<Vec3>& x, const EnergyParams& p,
                         const std::vector<Vec3>& v, std::vector<Vec3>& out) const;

    int colours() const { return int(colour_start_.size()) - 1; }
    Id chunks() const { return Id(chunk_order_.size()); }

  private:
    Mat38 hex_corners(const std::vector<Vec3>& x, Id h) const;
    // Runs kernel(first, last) on the elements [first, last) of every chunk, colour after
    // colour, the chunks of a colour in parallel, and returns the sum of what it returned
    // (over the chunks in a fixed order).
    template <class Kernel>
    double sum_by_colour(Kernel&& kernel) const;
    // The same with hex_kernel(h) on each hex whose 8 corner tets lie in one chunk,
    // triangle_kernel(r) on surface triangle r and tet_kernel(e) on every other element, in
    // element order.
    template <class HexKernel, class TetKernel, class TriangleKernel>
    double sum_by_colour_elements(HexKernel&& hex_kernel, TetKernel&& tet_kernel,
                                  TriangleKernel&& triangle_kernel) const;
    // Per surface triangle, the normal its energy is measured against at x
    // (Problem::triangle_normal).
    std::vector<Vec3> triangle_normals(const std::vector<Vec3>& x) const;
    // The held quads' term at x (Problem::HeldQuad), with E_q = w u(c)^2: its sum; when
    // `g` is given, each quad's gradient w u n / 2 added at its 4 vertices (n the unit
    // normal at c), and when `scatter` is given, scatter(q, w n n^T / 8), every block of
    // its Gauss-Newton Hessian (PSD). Quad after quad in order: deterministic.
    double held_quads_term(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>* g,
                           const std::function<void(Id, const Mat3&)>& scatter = {}) const;
    // Cuts the elements into chunks of `size` consecutive ones and colours them; false if
    // that needs more colours than the colouring can hold.
    bool colour_chunks(Id size);
    // F(x) and its gradient in g; the PSD Hessian of each finite hex goes to
    // scatter_hex(h, its blocks), that of each finite surface triangle r to
    // scatter_triangle(r, its 3 vertex ids, hr), that of each other finite element (plain
    // tets, and the corner tets of a hex split between chunks) to scatter_tet(e, its 4 vertex
    // ids, he), that of held quad q to scatter_quad(q, its one block).
    template <class ScatterHex, class ScatterTet, class ScatterTriangle>
    double assemble_hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                            ScatterHex&& scatter_hex, ScatterTet&& scatter_tet,
                            ScatterTriangle&& scatter_triangle,
                            const std::function<void(Id, const Mat3&)>& scatter_quad) const;

    // Where the element Hessians' blocks go, as offsets in the block row of the pair's lower
    // vertex id: per hex for its node pairs in hex_hessian_pairs order, per plain tet for
    // (a, b) (4 a + b), per triangle (3 a + b). Computed on first use: only the assembled
    // Hessian needs them.
    struct Slots {
        std::vector<std::array<uint16_t, 32>> hex;
        std::vector<std::array<uint16_t, 16>> tet;
        std::vector<std::array<uint16_t, 9>> triangle;
        std::vector<std::array<uint16_t, 16>> quad;  // held quads, (a, b) as 4 a + b
    };
    const Slots& hessian_slots() const;

    const Problem& problem_;
    Id chunk_size_ = 0;  // elements per chunk (the last one may be shorter)
    std::vector<Id>
        chunk_order_;  // chunk numbers (chunk k = elements from k chunk_size_), by colour
    std::vector<Id> colour_start_;  // offsets into chunk_order_
    BlockMatrix pattern_;           // row_start and col only
    mutable std::once_flag slots_once_;
    mutable Slots slots_;
};

}  // namespace hexmesh::untangle

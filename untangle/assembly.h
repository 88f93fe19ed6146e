// Assembly of the functional over all elements: energy, gradient and block Hessian.
#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <vector>

#include "untangle/problem.h"

namespace hexmesh::untangle {

// Symmetric sparse matrix of 3 x 3 blocks, one block row per vertex (CSR over vertices,
// columns sorted, the diagonal block always present).
struct BlockMatrix {
    std::vector<Id> row_start;  // #V + 1
    std::vector<Id> col;        // column vertex of each block
    std::vector<Mat3> block;    // values, same length as col

    Id rows() const { return Id(row_start.size()) - 1; }
    Id find(Id row, Id column) const;  // index into col/block, or -1
    void multiply(const std::vector<Vec3>& x, std::vector<Vec3>& y) const;  // y = A x
};

// Element statistics in target units (det S = 1 for a perfect element).
struct ElementStats {
    double min_det = 0;
    Id inverted = 0;  // elements with det S <= 0
};

// Precomputes the element schedule and the Hessian's block pattern, so that every sum below
// is parallel yet deterministic (the same input gives the same bits whatever the number of
// threads). Elements are cut into chunks of consecutive elements; chunks are coloured so
// that no two chunks of one colour share a vertex. Colours run one after the other, the chunks of a colour in parallel, the elements
// of a chunk in order: few synchronizations, and neighbouring elements share the cache.
class Assembly {
public:
    explicit Assembly(const Problem& problem);

    ElementStats stats(const std::vector<Vec3>& x) const;
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
    double diagonal_hessian(const std::vector<Vec3>& x, const EnergyParams& p,
                            std::vector<Vec3>& g, std::vector<Mat3>& diagonal) const;
    // out = H(x) v without storing H: element Hessians recomputed and applied one by one.
    void hessian_product(const std::vector<Vec3>& x, const EnergyParams& p,
                         const std::vector<Vec3>& v, std::vector<Vec3>& out) const;

    int colours() const { return int(colour_start_.size()) - 1; }
    Id chunks() const { return Id(chunk_start_.size()) - 1; }

private:
    Mat34 corners(const std::vector<Vec3>& x, Id e) const;
    // Runs kernel(e) for every element, colour after colour, the chunks of a colour in
    // parallel, each chunk's elements in order.
    template <class Kernel>
    void for_each_by_colour(Kernel&& kernel) const;
    // Cuts order_ into chunks of `size` elements and colours them; false if that needs more
    // colours than the colouring can hold.
    bool colour_chunks(Id size);
    // F(x) and its gradient in g; each finite element's PSD Hessian goes to scatter(e, he).
    template <class Scatter>
    double assemble_hessian(const std::vector<Vec3>& x, const EnergyParams& p,
                            std::vector<Vec3>& g, Scatter&& scatter) const;

    // Index into the pattern's blocks of block (a, b) of each element's Hessian (4 a + b),
    // computed on first use: only the assembled Hessian needs it.
    const std::vector<std::array<int32_t, 16>>& hessian_slots() const;

    const Problem& problem_;
    std::vector<Id> order_;         // elements, chunk after chunk, chunks sorted by colour
    std::vector<Id> chunk_start_;   // offsets into order_
    std::vector<Id> colour_start_;  // offsets into the chunks
    BlockMatrix pattern_;  // row_start and col only
    mutable std::once_flag slots_once_;
    mutable std::vector<std::array<int32_t, 16>> slots_;
};

}  // namespace hexmesh::untangle

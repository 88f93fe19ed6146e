// A symmetric sparse matrix of 3 x 3 single-precision blocks (the Hessian's shape) and its
// parallel, deterministic product with a vector of vertices.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh::untangle {

// One 3 x 3 block of the Hessian, in single precision: the matrix only shapes the Newton
// direction (its linear solve stops at a relative residual of 1e-2 or 1e-1) while energies,
// gradients and the line search stay in double; half the memory and half the traffic of
// every CG product.
using HessianBlock = Eigen::Matrix3f;
// Four floats in one SSE register (GCC vector extension): a vertex's x, y, z and a zero.
using Float4 = float __attribute__((vector_size(16)));

// Symmetric sparse matrix of 3 x 3 blocks stored by its upper triangle: block row a holds
// the blocks (a, b) with b >= a, columns sorted, the diagonal block (always present) first.
// Half the memory and half the traffic of a product; each stored block (a, b), a < b, acts
// as (a, b) and, transposed, as (b, a).
struct BlockMatrix {
    std::vector<Id> row_start;        // #V + 1
    std::vector<int32_t> col;         // column vertex of each block
    std::vector<HessianBlock> block;  // values, same length as col
    // Products run over ranges of consecutive rows: range k holds rows [k range_rows,
    // (k + 1) range_rows), and ranges are coloured so that two of one colour write no common
    // row of the result (their own rows and their columns): colours one after the other,
    // the ranges of a colour in parallel. The result does not depend on the thread count.
    Id range_rows = 0;
    std::vector<Id> range_order;                         // range numbers, by colour
    std::vector<Id> colour_start;                        // offsets into range_order
    mutable std::vector<Float4> product_x_, product_y_;  // multiply()'s x and y in float

    Id rows() const { return Id(row_start.size()) - 1; }
    // Index into col/block of the block (row, column), row <= column, or -1.
    Id find(Id row, Id column) const;
    // y = A x, computed in single precision like the blocks (x is rounded to float, the sums
    // are float); with component c in 0..2, only the couplings between coordinate c of the
    // vertices (the diagonal entries (c, c) of the blocks), summed in double, and y is zero
    // in the others. Uses scratch space in the matrix: not for concurrent calls.
    void multiply(const std::vector<Vec3>& x, std::vector<Vec3>& y, int component = -1) const;
    // Sets range_rows, range_order and colour_start from row_start and col.
    void schedule_products();
};

}  // namespace hexmesh::untangle

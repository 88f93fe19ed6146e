// BlockMatrix: block lookup, the product y = A x and the colouring of its row ranges.
#include "untangle/block_matrix.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bitset>
#include <cstring>
#include <stdexcept>

#include "untangle/group_by_colour.h"

namespace hexmesh::untangle {
namespace {

constexpr Id product_range_rows = 2048;  // rows per range of a Hessian product
constexpr int max_range_colours = 128;

// A block's columns as 4 floats (the 4th is junk and meets x's zero 4th entry), from its
// 9 consecutive floats without reading past them.
using Lane4 = int32_t __attribute__((vector_size(16)));
inline void block_columns(const HessianBlock& b, Float4& c0, Float4& c1, Float4& c2) {
    const float* p = b.data();
    Float4 tail;
    std::memcpy(&c0, p, sizeof c0);
    std::memcpy(&c1, p + 3, sizeof c1);
    std::memcpy(&tail, p + 5, sizeof tail);
    c2 = __builtin_shuffle(tail, Lane4{1, 2, 3, 3});
}

// Entry k of v in all four lanes.
inline Float4 broadcast(Float4 v, int k) {
    return __builtin_shuffle(v, Lane4{k, k, k, k});
}

// Rows [first, last) of y = A x in float: each stored block adds its product to its row and,
// transposed (a < b), to its column's row.
void rows_product(const BlockMatrix& m, const std::vector<Float4>& xf, std::vector<Float4>& yf,
                  Id first, Id last) {
    const auto& row_start = m.row_start;
    const auto& col = m.col;
    const auto& block = m.block;
    for (Id a = first; a < last; ++a) {
        Id k = row_start[a];
        const Float4 xa = xf[a], xa0 = broadcast(xa, 0), xa1 = broadcast(xa, 1),
                     xa2 = broadcast(xa, 2);
        Float4 c0, c1, c2;
        block_columns(block[k], c0, c1, c2);
        Float4 sum = c0 * xa0 + c1 * xa1 + c2 * xa2;
        for (++k; k < row_start[a + 1]; ++k) {
            block_columns(block[k], c0, c1, c2);
            const Float4 xb = xf[col[k]];
            sum += c0 * broadcast(xb, 0) + c1 * broadcast(xb, 1) + c2 * broadcast(xb, 2);
            // B^T xa: the three column dot products, by a transposition of their terms.
            const Float4 m0 = c0 * xa, m1 = c1 * xa, m2 = c2 * xa, zero{};
            const Float4 t0 = __builtin_shuffle(m0, m1, Lane4{0, 4, 1, 5});
            const Float4 t1 = __builtin_shuffle(m0, m1, Lane4{2, 6, 3, 7});
            const Float4 t2 = __builtin_shuffle(m2, zero, Lane4{0, 4, 1, 5});
            const Float4 t3 = __builtin_shuffle(m2, zero, Lane4{2, 6, 3, 7});
            yf[col[k]] += __builtin_shuffle(t0, t2, Lane4{0, 1, 4, 5}) +
                          __builtin_shuffle(t0, t2, Lane4{2, 3, 6, 7}) +
                          __builtin_shuffle(t1, t3, Lane4{0, 1, 4, 5});
        }
        yf[a] += sum;
    }
}

// Rows [first, last) of the product restricted to coordinate c, in double, summed into y.
void rows_component_product(const BlockMatrix& m, const std::vector<Vec3>& x, std::vector<Vec3>& y,
                            int c, Id first, Id last) {
    for (Id a = first; a < last; ++a) {
        Id k = m.row_start[a];
        const double xa = x[a][c];
        double s = double(m.block[k](c, c)) * xa;
        for (++k; k < m.row_start[a + 1]; ++k) {
            const double b = m.block[k](c, c);
            s += b * x[m.col[k]][c];
            y[m.col[k]][c] += b * xa;
        }
        y[a][c] += s;
    }
}

}  // namespace

Id BlockMatrix::find(Id row, Id column) const {
    const auto first = col.begin() + row_start[row], last = col.begin() + row_start[row + 1];
    const auto it = std::lower_bound(first, last, int32_t(column));
    return it != last && *it == column ? Id(it - col.begin()) : -1;
}

void BlockMatrix::multiply(const std::vector<Vec3>& x, std::vector<Vec3>& y, int component) const {
    y.resize(x.size());
    if (component >=
        0)  // summed into y; the whole product is summed in float and copied at the end
        tbb::parallel_for(tbb::blocked_range<size_t>(0, y.size(), 1 << 14),
                          [&](const tbb::blocked_range<size_t>& r) {
                              std::fill(y.begin() + r.begin(), y.begin() + r.end(), Vec3::Zero());
                          });
    const Id n = rows();
    if (n > 0 && colour_start.empty())
        throw std::logic_error("BlockMatrix::multiply before schedule_products()");
    // In single precision, as the blocks are.
    std::vector<Float4>&xf = product_x_, &yf = product_y_;
    if (component < 0) {
        xf.resize(x.size());
        yf.resize(x.size());
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, x.size(), 1 << 14),
            [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) {
                    xf[i] = Float4{float(x[i][0]), float(x[i][1]), float(x[i][2]), 0.0f};
                    yf[i] = Float4{};
                }
            });
    }
    for (size_t c = 0; c + 1 < colour_start.size(); ++c)
        tbb::parallel_for(colour_start[c], colour_start[c + 1], [&](Id m) {
            const Id first = range_order[m] * range_rows, last = std::min(n, first + range_rows);
            if (component < 0)
                rows_product(*this, xf, yf, first, last);
            else
                rows_component_product(*this, x, y, component, first, last);
        });
    if (component < 0)
        tbb::parallel_for(tbb::blocked_range<size_t>(0, y.size(), 1 << 14),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t i = r.begin(); i != r.end(); ++i)
                                  y[i] = Vec3(yf[i][0], yf[i][1], yf[i][2]);
                          });
}

void BlockMatrix::schedule_products() {
    const Id n = rows();
    range_rows = product_range_rows;
    const Id ranges = (n + range_rows - 1) / range_rows;
    // Greedy colouring: a range takes the first colour that no range writing one of its
    // rows has taken.
    std::vector<std::bitset<max_range_colours>> used(n);
    std::vector<int> colour(ranges);
    int colours = 0;
    for (Id k = 0; k < ranges; ++k) {
        const Id first = k * range_rows, last = std::min(n, first + range_rows);
        std::bitset<max_range_colours> taken;
        for (Id m = row_start[first]; m < row_start[last]; ++m) taken |= used[col[m]];
        int c = 0;
        while (c < max_range_colours && taken[c]) ++c;
        if (c == max_range_colours) {  // too scattered a numbering: one range, serial
            range_rows = std::max<Id>(n, 1);
            range_order.assign(n > 0 ? 1 : 0, 0);
            colour_start = n > 0 ? std::vector<Id>{0, 1} : std::vector<Id>{0};
            return;
        }
        colour[k] = c;
        colours = std::max(colours, c + 1);
        for (Id m = row_start[first]; m < row_start[last]; ++m) used[col[m]].set(c);
    }
    group_by_colour(colour, colours, colour_start, range_order);
}

}  // namespace hexmesh::untangle

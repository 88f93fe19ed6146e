#include "untangle/assembly.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace hexmesh::untangle {
namespace {

constexpr int max_colours = 512;
constexpr size_t grain = 2048;
constexpr Id chunk_elements = 256;  // elements per chunk (fewer if colouring needs it)

// Deterministic sum: the split depends on the size and grain only, never on the threads.
double deterministic_sum(const std::vector<double>& v) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<size_t>(0, v.size(), grain), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double s) {
            for (size_t i = r.begin(); i != r.end(); ++i) s += v[i];
            return s;
        },
        [](double a, double b) { return a + b; }, tbb::simple_partitioner());
}

}  // namespace

Id BlockMatrix::find(Id row, Id column) const {
    const auto first = col.begin() + row_start[row], last = col.begin() + row_start[row + 1];
    const auto it = std::lower_bound(first, last, column);
    return it != last && *it == column ? Id(it - col.begin()) : -1;
}

void BlockMatrix::multiply(const std::vector<Vec3>& x, std::vector<Vec3>& y) const {
    y.resize(x.size());
    tbb::parallel_for(tbb::blocked_range<Id>(0, rows(), 1024), [&](const tbb::blocked_range<Id>& r) {
        for (Id a = r.begin(); a != r.end(); ++a) {
            Vec3 s = Vec3::Zero();
            for (Id m = row_start[a]; m < row_start[a + 1]; ++m) s += block[m] * x[col[m]];
            y[a] = s;
        }
    });
}

Assembly::Assembly(const Problem& problem) : problem_(problem) {
    const Id nv = Id(problem.points.size()), ne = Id(problem.tets.size());
    for (const auto& t : problem.tets)
        for (Id v : t)
            if (v < 0 || v >= nv) throw std::invalid_argument("element refers to a missing vertex");

    // Chunks of consecutive elements (their targets stream from memory in order; the mesh's
    // own order usually keeps neighbours close), coloured; chunks shrink if a colouring needs
    // too many colours.
    order_.resize(ne);
    for (Id e = 0; e < ne; ++e) order_[e] = e;
    Id size = chunk_elements;
    while (!colour_chunks(size)) {
        if (size == 1) throw std::runtime_error("element colouring needs too many colours");
        size /= 2;
    }

    // Block pattern: vertex pairs sharing an element, plus every diagonal.
    std::vector<std::vector<Id>> adjacent(nv);
    for (Id v = 0; v < nv; ++v) adjacent[v].push_back(v);
    // Rows are short (about 20 blocks for hex corner tets): a linear search keeps each row
    // free of duplicates as it grows, so no row ever holds the 16 pairs of every element.
    for (const auto& t : problem.tets)
        for (Id a : t)
            for (Id b : t)
                if (std::find(adjacent[a].begin(), adjacent[a].end(), b) == adjacent[a].end())
                    adjacent[a].push_back(b);
    pattern_.row_start.assign(nv + 1, 0);
    for (Id v = 0; v < nv; ++v) {
        std::sort(adjacent[v].begin(), adjacent[v].end());
        pattern_.row_start[v + 1] = pattern_.row_start[v] + Id(adjacent[v].size());
    }
    pattern_.col.reserve(pattern_.row_start[nv]);
    for (Id v = 0; v < nv; ++v) {
        pattern_.col.insert(pattern_.col.end(), adjacent[v].begin(), adjacent[v].end());
        std::vector<Id>().swap(adjacent[v]);
    }
}

bool Assembly::colour_chunks(Id size) {
    const Id ne = Id(order_.size()), n_chunks = (ne + size - 1) / size;
    std::vector<std::bitset<max_colours>> used(problem_.points.size());
    std::vector<int> colour(n_chunks);
    int n_colours = 0;
    for (Id k = 0; k < n_chunks; ++k) {
        const Id first = k * size, last = std::min(ne, first + size);
        std::bitset<max_colours> taken;
        for (Id m = first; m < last; ++m)
            for (Id v : problem_.tets[order_[m]]) taken |= used[v];
        int c = 0;
        while (c < max_colours && taken[c]) ++c;
        if (c == max_colours) return false;
        colour[k] = c;
        n_colours = std::max(n_colours, c + 1);
        for (Id m = first; m < last; ++m)
            for (Id v : problem_.tets[order_[m]]) used[v].set(c);
    }
    // Chunks grouped by colour, in element order within a colour.
    colour_start_.assign(n_colours + 1, 0);
    for (Id k = 0; k < n_chunks; ++k) ++colour_start_[colour[k] + 1];
    for (int c = 0; c < n_colours; ++c) colour_start_[c + 1] += colour_start_[c];
    std::vector<Id> next(colour_start_.begin(), colour_start_.end() - 1), slot(n_chunks);
    for (Id k = 0; k < n_chunks; ++k) slot[next[colour[k]]++] = k;
    std::vector<Id> order;
    order.reserve(ne);
    chunk_start_.assign(1, 0);
    for (Id k : slot) {
        const Id first = k * size, last = std::min(ne, first + size);
        order.insert(order.end(), order_.begin() + first, order_.begin() + last);
        chunk_start_.push_back(Id(order.size()));
    }
    order_.swap(order);
    return true;
}

BlockMatrix Assembly::empty_hessian() const {
    BlockMatrix h = pattern_;
    h.block.assign(h.col.size(), Mat3::Zero());
    return h;
}

Mat34 Assembly::corners(const std::vector<Vec3>& x, Id e) const {
    Mat34 y;
    for (int a = 0; a < 4; ++a) y.col(a) = x[problem_.tets[e][a]];
    return y;
}

ElementStats Assembly::stats(const std::vector<Vec3>& x) const {
    const Id ne = Id(problem_.tets.size());
    std::vector<double> det(ne);
    tbb::parallel_for(Id(0), ne, [&](Id e) { det[e] = tet_det(corners(x, e), problem_.targets[e]); });
    ElementStats s;
    s.min_det = ne ? *std::min_element(det.begin(), det.end()) : 0;
    s.inverted = Id(std::count_if(det.begin(), det.end(), [](double d) { return !(d > 0); }));
    return s;
}

double Assembly::energy(const std::vector<Vec3>& x, const EnergyParams& p) const {
    const Id ne = Id(problem_.tets.size());
    std::vector<double> value(ne);
    tbb::parallel_for(Id(0), ne, [&](Id e) { value[e] = tet_energy(corners(x, e), problem_.targets[e], p); });
    return deterministic_sum(value);
}


template <class Kernel>
void Assembly::for_each_by_colour(Kernel&& kernel) const {
    for (int c = 0; c < colours(); ++c)
        tbb::parallel_for(colour_start_[c], colour_start_[c + 1], [&](Id k) {
            for (Id m = chunk_start_[k]; m < chunk_start_[k + 1]; ++m) kernel(order_[m]);
        });
}

template <class Scatter>
double Assembly::assemble_hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                                  Scatter&& scatter) const {
    g.assign(x.size(), Vec3::Zero());
    std::vector<double> value(problem_.tets.size());
    for_each_by_colour([&](Id e) {
        Mat34 ge;
        Mat12 he;
        value[e] = tet_energy_hessian(corners(x, e), problem_.targets[e], p, ge, he);
        if (!std::isfinite(value[e])) return;
        for (int a = 0; a < 4; ++a) g[problem_.tets[e][a]] += ge.col(a);
        scatter(e, he);
    });
    return deterministic_sum(value);
}

double Assembly::diagonal_hessian(const std::vector<Vec3>& x, const EnergyParams& p,
                                  std::vector<Vec3>& g, std::vector<Mat3>& diagonal) const {
    diagonal.assign(x.size(), Mat3::Zero());
    return assemble_hessian(x, p, g, [&](Id e, const Mat12& he) {
        for (int a = 0; a < 4; ++a) diagonal[problem_.tets[e][a]] += he.block<3, 3>(3 * a, 3 * a);
    });
}

void Assembly::hessian_product(const std::vector<Vec3>& x, const EnergyParams& p,
                               const std::vector<Vec3>& v, std::vector<Vec3>& out) const {
    out.assign(x.size(), Vec3::Zero());
    for_each_by_colour([&](Id e) {
        Mat34 ge;
        Mat12 he;
        if (!std::isfinite(tet_energy_hessian(corners(x, e), problem_.targets[e], p, ge, he))) return;
        const auto& t = problem_.tets[e];
        Eigen::Matrix<double, 12, 1> ve;
        for (int a = 0; a < 4; ++a) ve.segment<3>(3 * a) = v[t[a]];
        const Eigen::Matrix<double, 12, 1> he_v = he * ve;
        for (int a = 0; a < 4; ++a) out[t[a]] += he_v.segment<3>(3 * a);
    });
}

double Assembly::gradient(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g) const {
    g.assign(x.size(), Vec3::Zero());
    std::vector<double> value(problem_.tets.size());
    for_each_by_colour([&](Id e) {
        Mat34 ge;
        value[e] = tet_energy_gradient(corners(x, e), problem_.targets[e], p, ge);
        if (!std::isfinite(value[e])) return;
        for (int a = 0; a < 4; ++a) g[problem_.tets[e][a]] += ge.col(a);
    });
    return deterministic_sum(value);
}

const std::vector<std::array<int32_t, 16>>& Assembly::hessian_slots() const {
    std::call_once(slots_once_, [this] {
        if (pattern_.col.size() > size_t(std::numeric_limits<int32_t>::max()))
            throw std::runtime_error("Hessian pattern too large for 32-bit block indices");
        slots_.resize(problem_.tets.size());
        tbb::parallel_for(size_t(0), problem_.tets.size(), [&](size_t e) {
            const auto& t = problem_.tets[e];
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b) slots_[e][4 * a + b] = int32_t(pattern_.find(t[a], t[b]));
        });
    });
    return slots_;
}

double Assembly::hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                         BlockMatrix& h) const {
    const std::vector<std::array<int32_t, 16>>& slots = hessian_slots();
    std::fill(h.block.begin(), h.block.end(), Mat3::Zero());
    return assemble_hessian(x, p, g, [&](Id e, const Mat12& he) {
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) h.block[slots[e][4 * a + b]] += he.block<3, 3>(3 * a, 3 * b);
    });
}

}  // namespace hexmesh::untangle

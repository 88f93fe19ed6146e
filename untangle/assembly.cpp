// Assembly: the element schedule, the Hessian's block pattern, and the sums of energies,
// gradients and Hessians over all elements.
#include "untangle/assembly.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "hexmesh/core/parallel_sum.h"
#include "untangle/group_by_colour.h"

namespace hexmesh::untangle {
namespace {

constexpr int max_colours = 512;
constexpr size_t grain = 2048;

// Position in hex_hessian_pairs of the pair of hex nodes (a, b), in either order; -1 for
// the body diagonals.
constexpr std::array<std::array<int, 8>, 8> hex_pair_index = [] {
    std::array<std::array<int, 8>, 8> index{};
    for (auto& row : index)
        for (int& i : row) i = -1;
    for (int q = 0; q < int(hex_hessian_pairs.size()); ++q) {
        const auto& [a, b] = hex_hessian_pairs[q];
        index[a][b] = index[b][a] = q;
    }
    return index;
}();

// The factor that turns the energy (and its derivatives) of a tet of weight w into that of a
// unit target's, 1/6, when p.equal_weights; 1 otherwise. A hex's 8 corner tets each weigh
// edges.prod() / 6. Surface triangles keep their weights.
double weight_factor(double w, const EnergyParams& p) {
    return p.equal_weights && w > 0 ? (1.0 / 6) / w : 1.0;
}
double hex_weight_factor(const Vec3& edges, const EnergyParams& p) {
    const double volume = edges.prod();  // (1/6) / (volume / 6)
    return p.equal_weights && volume > 0 ? 1.0 / volume : 1.0;
}

}  // namespace

Assembly::Assembly(const Problem& problem, Id chunk_elements) : problem_(problem) {
    const Id nv = Id(problem.points.size()), ne = problem.num_elements();
    if (nv > std::numeric_limits<int32_t>::max())
        throw std::invalid_argument("too many vertices for 32-bit Hessian columns");
    if (problem.hex_edges.size() != problem.hexes.size() ||
        problem.targets.size() != problem.tets.size() ||
        problem.triangle_targets.size() != problem.triangles.size())
        throw std::invalid_argument("one target per element is required");
    const auto valid = [nv](Id v) { return v >= 0 && v < nv; };
    for (const auto& h : problem.hexes)
        if (!std::all_of(h.begin(), h.end(), valid))
            throw std::invalid_argument("element refers to a missing vertex");
    for (const auto& t : problem.tets)
        if (!std::all_of(t.begin(), t.end(), valid))
            throw std::invalid_argument("element refers to a missing vertex");
    for (const auto& t : problem.triangles)
        if (!std::all_of(t.begin(), t.end(), valid))
            throw std::invalid_argument("element refers to a missing vertex");
    for (const HeldQuad& q : problem.held_quads)
        if (!std::all_of(q.nodes.begin(), q.nodes.end(), valid))
            throw std::invalid_argument("held quad refers to a missing vertex");
    if (!problem.held_quads.empty() && (!problem.surface_value || !problem.surface_normal))
        throw std::invalid_argument("held quads need the surface's value and normal");

    // Chunks of consecutive elements (a hex's corner tets together, targets streaming from
    // memory in order; the mesh's own order usually keeps neighbours close), coloured; chunks
    // shrink if a colouring needs too many colours.
    Id size = std::max<Id>(chunk_elements, 1);
    while (!colour_chunks(size)) {
        if (size == 1) throw std::runtime_error("element colouring needs too many colours");
        size /= 2;
    }

    // Block pattern: vertex pairs (a, b), a <= b, sharing an element, plus every diagonal.
    std::vector<std::vector<int32_t>> adjacent(nv);
    for (Id v = 0; v < nv; ++v) adjacent[v].push_back(int32_t(v));
    // Rows are short (about 20 blocks for hex corner tets): a linear search keeps each row
    // free of duplicates as it grows, so no row ever holds the 16 pairs of every element.
    const auto join = [&adjacent](Id a, Id b) {
        if (a < b &&
            std::find(adjacent[a].begin(), adjacent[a].end(), int32_t(b)) == adjacent[a].end())
            adjacent[a].push_back(int32_t(b));
    };
    for (Id e = 0; e < ne; ++e) {
        const ElementNodes t = problem.element(e);
        for (Id a : t)
            for (Id b : t) join(a, b);
    }
    for (const HeldQuad& q : problem.held_quads)
        for (Id a : q.nodes)
            for (Id b : q.nodes) join(a, b);
    pattern_.row_start.assign(nv + 1, 0);
    for (Id v = 0; v < nv; ++v) {
        if (adjacent[v].size() > std::numeric_limits<uint16_t>::max())
            throw std::invalid_argument("a vertex shares elements with too many others");
        std::sort(adjacent[v].begin(), adjacent[v].end());
        pattern_.row_start[v + 1] = pattern_.row_start[v] + Id(adjacent[v].size());
    }
    pattern_.col.reserve(pattern_.row_start[nv]);
    for (Id v = 0; v < nv; ++v) {
        pattern_.col.insert(pattern_.col.end(), adjacent[v].begin(), adjacent[v].end());
        std::vector<int32_t>().swap(adjacent[v]);
    }
    pattern_.schedule_products();
}

bool Assembly::colour_chunks(Id size) {
    const Id ne = problem_.num_elements(), n_chunks = (ne + size - 1) / size;
    std::vector<std::bitset<max_colours>> used(problem_.points.size());
    std::vector<int> colour(n_chunks);
    int n_colours = 0;
    for (Id k = 0; k < n_chunks; ++k) {
        const Id first = k * size, last = std::min(ne, first + size);
        std::bitset<max_colours> taken;
        for (Id e = first; e < last; ++e)
            for (Id v : problem_.element(e)) taken |= used[v];
        int c = 0;
        while (c < max_colours && taken[c]) ++c;
        if (c == max_colours) return false;
        colour[k] = c;
        n_colours = std::max(n_colours, c + 1);
        for (Id e = first; e < last; ++e)
            for (Id v : problem_.element(e)) used[v].set(c);
    }
    group_by_colour(colour, n_colours, colour_start_, chunk_order_);
    chunk_size_ = size;
    return true;
}

BlockMatrix Assembly::empty_hessian() const {
    BlockMatrix h = pattern_;
    h.block.assign(h.col.size(), HessianBlock::Zero());
    return h;
}

ElementStats Assembly::stats(const std::vector<Vec3>& x) const {
    // Minimum and count do not depend on the order of the terms: any split is deterministic.
    const Id ne = problem_.num_elements(), first_triangle = problem_.first_triangle();
    if (ne == 0) return {};
    const std::vector<Vec3> normals = triangle_normals(x);
    return tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, ne, grain),
        ElementStats{std::numeric_limits<double>::infinity(), 0},
        [&](const tbb::blocked_range<Id>& r, ElementStats s) {
            for (Id e = r.begin(); e != r.end(); ++e) {
                const Id t = e - first_triangle;
                const double d = e < first_triangle
                                     ? problem_.det(x, e)
                                     : triangle_det(Problem::corners(x, problem_.triangles[t]),
                                                    normals[t], problem_.triangle_targets[t]);
                if (!(d >= s.min_det)) s.min_det = d;  // a NaN wins: it must not go unseen
                s.inverted += !(d > 0);
            }
            return s;
        },
        [](ElementStats a, const ElementStats& b) {
            if (!(b.min_det >= a.min_det)) a.min_det = b.min_det;
            a.inverted += b.inverted;
            return a;
        });
}

std::vector<Vec3> Assembly::triangle_normals(const std::vector<Vec3>& x) const {
    std::vector<Vec3> normals(problem_.triangles.size());
    tbb::parallel_for(size_t(0), normals.size(), [&](size_t r) {
        normals[r] = problem_.triangle_normal(x, problem_.triangles[r]);
    });
    return normals;
}

Mat38 Assembly::hex_corners(const std::vector<Vec3>& x, Id h) const {
    Mat38 y;
    for (int a = 0; a < 8; ++a) y.col(a) = x[problem_.hexes[h][a]];
    return y;
}

double Assembly::energy(const std::vector<Vec3>& x, const EnergyParams& p) const {
    // Summed by hex (8 corner tets at once), plain tet and triangle.
    const Id hexes = Id(problem_.hexes.size()), tets = Id(problem_.tets.size());
    const std::vector<Vec3> normals = triangle_normals(x);
    const double elements =
        deterministic_sum(size_t(hexes + tets) + problem_.triangles.size(), grain, [&](size_t u) {
            if (Id(u) < hexes) {
                const Vec3& edges = problem_.hex_edges[u];
                return hex_weight_factor(edges, p) * hex_energy(hex_corners(x, Id(u)), edges, p);
            }
            if (Id(u) < hexes + tets) {
                const TetTarget& t = problem_.targets[u - hexes];
                return weight_factor(t.weight, p) *
                       tet_energy(Problem::corners(x, problem_.tets[u - hexes]), t, p);
            }
            const Id r = Id(u) - hexes - tets;
            return triangle_energy(Problem::corners(x, problem_.triangles[r]), normals[r],
                                   problem_.triangle_targets[r], p);
        });
    return elements + held_quads_term(x, p, nullptr);
}

double Assembly::held_quads_term(const std::vector<Vec3>& x, const EnergyParams& p,
                                 std::vector<Vec3>* g,
                                 const std::function<void(Id, const Mat3&)>& scatter) const {
    const std::vector<HeldQuad>& quads = problem_.held_quads;
    if (quads.empty()) return 0;
    std::vector<double> value(quads.size());
    std::vector<Vec3> normal(quads.size());
    tbb::parallel_for(size_t(0), quads.size(), [&](size_t q) {
        const auto& n = quads[q].nodes;
        const Vec3 c = (x[n[0]] + x[n[1]] + x[n[2]] + x[n[3]]) / 4;
        value[q] = problem_.surface_value(c);
        normal[q] = problem_.surface_normal(n[0], c).normalized();
    });
    double sum = 0;
    for (size_t q = 0; q < quads.size(); ++q) {
        const double w = p.equal_weights ? quads[q].unit_weight : quads[q].weight, u = value[q];
        sum += w * u * u;
        if (g)
            for (Id v : quads[q].nodes) (*g)[v] += (w * u / 2) * normal[q];
        if (scatter) scatter(Id(q), (w / 8) * normal[q] * normal[q].transpose());
    }
    return sum;
}

template <class Kernel>
double Assembly::sum_by_colour(Kernel&& kernel) const {
    const Id ne = problem_.num_elements();
    std::vector<double> chunk_value(chunks(), 0.0);
    for (int c = 0; c < colours(); ++c)
        tbb::parallel_for(colour_start_[c], colour_start_[c + 1], [&](Id m) {
            const Id k = chunk_order_[m];
            chunk_value[k] = kernel(k * chunk_size_, std::min(ne, (k + 1) * chunk_size_));
        });
    return deterministic_sum(chunk_value.size(), grain, [&](size_t k) { return chunk_value[k]; });
}

template <class HexKernel, class TetKernel, class TriangleKernel>
double Assembly::sum_by_colour_elements(HexKernel&& hex_kernel, TetKernel&& tet_kernel,
                                        TriangleKernel&& triangle_kernel) const {
    const Id first_triangle = problem_.first_triangle();
    return sum_by_colour([&](Id first, Id last) {
        double s = 0;
        for (Id e = first; e < last;) {
            if (problem_.is_hex_corner(e) && e % 8 == 0 && e + 8 <= last) {
                s += hex_kernel(e / 8);
                e += 8;
            } else if (e >= first_triangle) {
                s += triangle_kernel(e - first_triangle);
                ++e;
            } else {
                s += tet_kernel(e);
                ++e;
            }
        }
        return s;
    });
}

template <class ScatterHex, class ScatterTet, class ScatterTriangle>
double Assembly::assemble_hessian(const std::vector<Vec3>& x, const EnergyParams& p,
                                  std::vector<Vec3>& g, ScatterHex&& scatter_hex,
                                  ScatterTet&& scatter_tet, ScatterTriangle&& scatter_triangle,
                                  const std::function<void(Id, const Mat3&)>& scatter_quad) const {
    g.assign(x.size(), Vec3::Zero());
    const std::vector<Vec3> normals = triangle_normals(x);
    const double elements = sum_by_colour_elements(
        [&](Id h) {
            Mat38 gh;
            HexHessian hh;
            const Vec3& edges = problem_.hex_edges[h];
            double value = hex_energy_hessian(hex_corners(x, h), edges, p, gh, hh);
            if (!std::isfinite(value)) return value;
            if (const double f = hex_weight_factor(edges, p); f != 1) {
                value *= f, gh *= f;
                for (const auto& [a, b] : hex_hessian_pairs) hh.block[a][b] *= f;
            }
            for (int a = 0; a < 8; ++a) g[problem_.hexes[h][a]] += gh.col(a);
            scatter_hex(h, hh);
            return value;
        },
        [&](Id e) {
            const std::array<Id, 4> t = problem_.element(e).id;
            Mat34 ge;
            Mat12 he;
            const TetTarget target = problem_.target(e);
            double value = tet_energy_hessian(Problem::corners(x, t), target, p, ge, he);
            if (!std::isfinite(value)) return value;
            if (const double f = weight_factor(target.weight, p); f != 1)
                value *= f, ge *= f, he *= f;
            for (int a = 0; a < 4; ++a) g[t[a]] += ge.col(a);
            scatter_tet(e, t, he);
            return value;
        },
        [&](Id r) {
            const std::array<Id, 3>& t = problem_.triangles[r];
            Mat3 gr;
            Mat9 hr;
            const double value = triangle_energy_hessian(Problem::corners(x, t), normals[r],
                                                         problem_.triangle_targets[r], p, gr, hr);
            if (!std::isfinite(value)) return value;
            for (int a = 0; a < 3; ++a) g[t[a]] += gr.col(a);
            scatter_triangle(r, t, hr);
            return value;
        });
    return elements + held_quads_term(x, p, &g, scatter_quad);
}

double Assembly::diagonal_hessian(const std::vector<Vec3>& x, const EnergyParams& p,
                                  std::vector<Vec3>& g, std::vector<Mat3>& diagonal) const {
    diagonal.assign(x.size(), Mat3::Zero());
    return assemble_hessian(
        x, p, g,
        [&](Id h, const HexHessian& hh) {
            for (int a = 0; a < 8; ++a) diagonal[problem_.hexes[h][a]] += hh.block[a][a];
        },
        [&](Id, const std::array<Id, 4>& t, const Mat12& he) {
            for (int a = 0; a < 4; ++a) diagonal[t[a]] += he.block<3, 3>(3 * a, 3 * a);
        },
        [&](Id, const std::array<Id, 3>& t, const Mat9& hr) {
            for (int a = 0; a < 3; ++a) diagonal[t[a]] += hr.block<3, 3>(3 * a, 3 * a);
        },
        [&](Id q, const Mat3& block) {
            for (Id v : problem_.held_quads[q].nodes) diagonal[v] += block;
        });
}

void Assembly::hessian_product(const std::vector<Vec3>& x, const EnergyParams& p,
                               const std::vector<Vec3>& v, std::vector<Vec3>& out) const {
    out.assign(x.size(), Vec3::Zero());
    std::vector<Vec3> g;
    assemble_hessian(
        x, p, g,
        [&](Id h, const HexHessian& hh) {
            const auto& n = problem_.hexes[h];
            for (const auto& [a, b] : hex_hessian_pairs) {
                out[n[a]] += hh.block[a][b] * v[n[b]];
                if (a != b) out[n[b]] += hh.block[a][b].transpose() * v[n[a]];
            }
        },
        [&](Id, const std::array<Id, 4>& t, const Mat12& he) {
            Eigen::Matrix<double, 12, 1> ve;
            for (int a = 0; a < 4; ++a) ve.segment<3>(3 * a) = v[t[a]];
            const Eigen::Matrix<double, 12, 1> he_v = he * ve;
            for (int a = 0; a < 4; ++a) out[t[a]] += he_v.segment<3>(3 * a);
        },
        [&](Id, const std::array<Id, 3>& t, const Mat9& hr) {
            Eigen::Matrix<double, 9, 1> vr;
            for (int a = 0; a < 3; ++a) vr.segment<3>(3 * a) = v[t[a]];
            const Eigen::Matrix<double, 9, 1> hr_v = hr * vr;
            for (int a = 0; a < 3; ++a) out[t[a]] += hr_v.segment<3>(3 * a);
        },
        [&](Id q, const Mat3& block) {  // every block the same: block (sum of v) at each
            const auto& n = problem_.held_quads[q].nodes;
            const Vec3 block_v = block * (v[n[0]] + v[n[1]] + v[n[2]] + v[n[3]]);
            for (Id a : n) out[a] += block_v;
        });
}

double Assembly::gradient(const std::vector<Vec3>& x, const EnergyParams& p,
                          std::vector<Vec3>& g) const {
    g.assign(x.size(), Vec3::Zero());
    const std::vector<Vec3> normals = triangle_normals(x);
    const double elements = sum_by_colour_elements(
        [&](Id h) {
            Mat38 gh;
            const Vec3& edges = problem_.hex_edges[h];
            const double value = hex_energy(hex_corners(x, h), edges, p, &gh);
            if (!std::isfinite(value)) return value;
            const double f = hex_weight_factor(edges, p);
            for (int a = 0; a < 8; ++a) g[problem_.hexes[h][a]] += f * gh.col(a);
            return f * value;
        },
        [&](Id e) {
            const std::array<Id, 4> t = problem_.element(e).id;
            Mat34 ge;
            const TetTarget target = problem_.target(e);
            const double value = tet_energy_gradient(Problem::corners(x, t), target, p, ge);
            if (!std::isfinite(value)) return value;
            const double f = weight_factor(target.weight, p);
            for (int a = 0; a < 4; ++a) g[t[a]] += f * ge.col(a);
            return f * value;
        },
        [&](Id r) {
            const std::array<Id, 3>& t = problem_.triangles[r];
            Mat3 gr;
            const double value = triangle_energy_gradient(Problem::corners(x, t), normals[r],
                                                          problem_.triangle_targets[r], p, gr);
            if (std::isfinite(value))
                for (int a = 0; a < 3; ++a) g[t[a]] += gr.col(a);
            return value;
        });
    return elements + held_quads_term(x, p, &g);
}

const Assembly::Slots& Assembly::hessian_slots() const {
    std::call_once(slots_once_, [this] {
        const auto offset = [this](Id a, Id b) {
            const Id row = std::min(a, b);
            return uint16_t(pattern_.find(row, std::max(a, b)) - pattern_.row_start[row]);
        };
        slots_.hex.resize(problem_.hexes.size());
        tbb::parallel_for(size_t(0), problem_.hexes.size(), [&](size_t h) {
            const auto& n = problem_.hexes[h];
            for (size_t q = 0; q < hex_hessian_pairs.size(); ++q)
                slots_.hex[h][q] = offset(n[hex_hessian_pairs[q][0]], n[hex_hessian_pairs[q][1]]);
        });
        slots_.tet.resize(problem_.tets.size());
        tbb::parallel_for(size_t(0), problem_.tets.size(), [&](size_t e) {
            const auto& t = problem_.tets[e];
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b) slots_.tet[e][4 * a + b] = offset(t[a], t[b]);
        });
        slots_.triangle.resize(problem_.triangles.size());
        tbb::parallel_for(size_t(0), problem_.triangles.size(), [&](size_t r) {
            const auto& t = problem_.triangles[r];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) slots_.triangle[r][3 * a + b] = offset(t[a], t[b]);
        });
        slots_.quad.resize(problem_.held_quads.size());
        tbb::parallel_for(size_t(0), problem_.held_quads.size(), [&](size_t q) {
            const auto& n = problem_.held_quads[q].nodes;
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b) slots_.quad[q][4 * a + b] = offset(n[a], n[b]);
        });
    });
    return slots_;
}

double Assembly::hessian(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& g,
                         BlockMatrix& h) const {
    const Slots& slots = hessian_slots();
    const Id hex_elements = 8 * Id(problem_.hexes.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, h.block.size(), 1 << 14),
                      [&](const tbb::blocked_range<size_t>& r) {
                          std::fill(h.block.begin() + r.begin(), h.block.begin() + r.end(),
                                    HessianBlock::Zero());
                      });
    // Block (a, b) of the element goes to the row of the lower vertex id, transposed if that
    // is b's.
    return assemble_hessian(
        x, p, g,
        [&](Id hex, const HexHessian& hh) {
            const auto& n = problem_.hexes[hex];
            for (size_t q = 0; q < hex_hessian_pairs.size(); ++q) {
                const auto& [a, b] = hex_hessian_pairs[q];
                const HessianBlock block = hh.block[a][b].cast<float>();
                HessianBlock& target =
                    h.block[h.row_start[std::min(n[a], n[b])] + slots.hex[hex][q]];
                if (a == b || n[a] < n[b])
                    target += block;
                else if (n[a] > n[b])
                    target += block.transpose();
                else  // two nodes of the hex coincide: both blocks land on the diagonal
                    target += block + block.transpose();
            }
        },
        [&](Id e, const std::array<Id, 4>& t, const Mat12& he) {
            for (int a = 0; a < 4; ++a) {
                HessianBlock* row = h.block.data() + h.row_start[t[a]];
                for (int b = 0; b < 4; ++b) {
                    if (t[a] > t[b]) continue;  // stored from t[b]'s row as (b, a)
                    const uint16_t slot =
                        e < hex_elements
                            ? slots.hex[e / 8][hex_pair_index[hex_corner_tets[e % 8][a]]
                                                             [hex_corner_tets[e % 8][b]]]
                            : slots.tet[e - hex_elements][4 * a + b];
                    row[slot] += he.block<3, 3>(3 * a, 3 * b).cast<float>();
                }
            }
        },
        [&](Id r, const std::array<Id, 3>& t, const Mat9& hr) {
            for (int a = 0; a < 3; ++a) {
                HessianBlock* row = h.block.data() + h.row_start[t[a]];
                for (int b = 0; b < 3; ++b)
                    if (t[a] <= t[b])
                        row[slots.triangle[r][3 * a + b]] +=
                            hr.block<3, 3>(3 * a, 3 * b).cast<float>();
            }
        },
        [&](Id q, const Mat3& block) {  // symmetric: no transpose for the lower vertex's row
            const auto& n = problem_.held_quads[q].nodes;
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b)
                    if (n[a] <= n[b])
                        h.block[h.row_start[n[a]] + slots.quad[q][4 * a + b]] +=
                            block.cast<float>();
        });
}

}  // namespace hexmesh::untangle

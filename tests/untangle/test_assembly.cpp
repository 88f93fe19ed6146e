#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <map>
#include <random>

#include "grid_problem.h"
#include "untangle/assembly.h"
#include "untangle/constraints.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

namespace {

// The assembled gradient at the given vertices against central differences of the energy.
void expect_gradient_matches_finite_differences(const Problem& p, const Assembly& a,
                                                const EnergyParams& params,
                                                std::initializer_list<Id> vertices) {
    std::vector<Vec3> g;
    a.gradient(p.points, params, g);
    std::vector<Vec3> x = p.points;
    for (Id v : vertices)
        for (int c = 0; c < 3; ++c) {
            const double h = 1e-6, x0 = x[v][c];
            x[v][c] = x0 + h;
            const double fp = a.energy(x, params);
            x[v][c] = x0 - h;
            const double fm = a.energy(x, params);
            x[v][c] = x0;
            EXPECT_NEAR(g[v][c], (fp - fm) / (2 * h), 1e-5 * (1 + std::abs(g[v][c])));
        }
}

}  // namespace

TEST(Assembly, GradientMatchesFiniteDifferencesOfTheSum) {
    const Problem p = test_support::displaced_grid_problem(3, 0.3, 1);
    expect_gradient_matches_finite_differences(p, Assembly(p), {0.8, 0.05},
                                               {Id(21), Id(22), Id(26), Id(41)});
}

namespace {

// The assembled energy, gradient and Hessian against serial sums over the elements: the
// Hessian holds exactly the blocks (a, b), a <= b, of the summed element Hessians; its
// products (whole, one coordinate, and without a matrix) are those of the whole matrix.
// With params.equal_weights each tet's terms are scaled to those of a unit weight (1/6).
// Held quads add w u(c)^2, w u n / 2 at each vertex and w n n^T / 8 at each pair (n the unit
// normal at c, w the unit weight with params.equal_weights).
void expect_assembly_matches_serial_sums(const Problem& p, const Assembly& a,
                                         const EnergyParams params = {0.8, 0.1}) {
    BlockMatrix h = a.empty_hessian();
    std::vector<Vec3> g;
    const double f = a.hessian(p.points, params, g, h);
    // Chunks of one colour share no vertex: no update is lost, the sums are the serial ones.
    double serial_f = 0;
    std::vector<Vec3> serial_g(p.points.size(), Vec3::Zero());
    std::map<std::pair<Id, Id>, Mat3> serial_h;     // every block (a, b), both triangles
    std::map<std::pair<Id, Id>, double> magnitude;  // the sum of the norms of its terms
    for (Id e = 0; e < p.num_elements(); ++e) {
        const ElementNodes t = p.element(e);
        Eigen::MatrixXd ge, he;  // 3 x size, 3 size x 3 size
        if (p.is_triangle(e)) {
            const Id r = e - p.first_triangle();
            Mat3 gr;
            Mat9 hr;
            serial_f += triangle_energy_hessian(Problem::corners(p.points, p.triangles[r]),
                                                p.triangle_normal(p.points, p.triangles[r]),
                                                p.triangle_targets[r], params, gr, hr);
            ge = gr, he = hr;
        } else {
            Mat34 gt;
            Mat12 ht;
            const double scale = params.equal_weights ? (1.0 / 6) / p.target(e).weight : 1.0;
            serial_f += scale * tet_energy_hessian(Problem::corners(p.points, t.id), p.target(e),
                                                   params, gt, ht);
            ge = scale * gt, he = scale * ht;
        }
        for (int c = 0; c < t.size; ++c) serial_g[t[c]] += ge.col(c);
        for (int c = 0; c < t.size; ++c)
            for (int d = 0; d < t.size; ++d) {
                auto [it, fresh] = serial_h.try_emplace({t[c], t[d]}, Mat3::Zero());
                it->second += he.block<3, 3>(3 * c, 3 * d);
                magnitude[{t[c], t[d]}] += he.block<3, 3>(3 * c, 3 * d).norm();
            }
    }
    for (const HeldQuad& q : p.held_quads) {
        const auto& n = q.nodes;
        const Vec3 c = (p.points[n[0]] + p.points[n[1]] + p.points[n[2]] + p.points[n[3]]) / 4;
        const double w = params.equal_weights ? q.unit_weight : q.weight, u = p.surface_value(c);
        const Vec3 normal = p.surface_normal(n[0], c).normalized();
        serial_f += w * u * u;
        for (Id a : n) serial_g[a] += w * u / 2 * normal;
        for (Id a : n)
            for (Id b : n) {
                auto [it, fresh] = serial_h.try_emplace({a, b}, Mat3::Zero());
                it->second += w / 8 * normal * normal.transpose();
                magnitude[{a, b}] += w / 8;
            }
    }
    EXPECT_NEAR(a.energy(p.points, params), f, 1e-12 * std::abs(f));
    std::vector<Vec3> g_only;
    EXPECT_EQ(a.gradient(p.points, params, g_only), f);
    EXPECT_EQ(g_only, g);
    ASSERT_TRUE(std::isfinite(serial_f));
    EXPECT_NEAR(f, serial_f, 1e-12 * std::abs(serial_f));
    for (size_t v = 0; v < g.size(); ++v)
        EXPECT_LT((g[v] - serial_g[v]).norm(), 1e-10 * (1 + serial_g[v].norm()));
    // Stored: exactly the blocks (a, b) with a <= b, each the serial sum (to single precision:
    // each term is rounded as it is added).
    Id stored = 0;
    for (Id r = 0; r < h.rows(); ++r) {
        EXPECT_EQ(h.col[h.row_start[r]], r) << "the diagonal block comes first";
        for (Id m = h.row_start[r]; m < h.row_start[r + 1]; ++m, ++stored) {
            ASSERT_LE(r, h.col[m]);
            const Mat3& want = serial_h.at({r, Id(h.col[m])});
            const double scale = 1 + magnitude.at({r, Id(h.col[m])});
            EXPECT_LT((h.block[m].cast<double>() - want).norm(), 1e-6 * scale)
                << r << " " << h.col[m];
        }
    }
    EXPECT_EQ(size_t(2 * stored - h.rows()), serial_h.size());
    std::vector<Vec3> v(p.points.size()), hv, hv_free, want(p.points.size(), Vec3::Zero());
    for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3(std::sin(i), std::cos(3.0 * i), 0.5);
    // Rounding is relative to the size of the terms summed (which may cancel), not of the sum.
    std::vector<double> terms(p.points.size(), 0.0);
    for (const auto& [ab, block] : serial_h) {
        want[ab.first] += block * v[ab.second];
        terms[ab.first] += magnitude.at(ab) * v[ab.second].norm();
    }
    h.multiply(v, hv);
    a.hessian_product(p.points, params, v, hv_free);
    for (size_t i = 0; i < v.size(); ++i) {
        EXPECT_LT((hv[i] - want[i]).norm(), 1e-5 * (1 + want[i].norm()));
        EXPECT_LT((hv_free[i] - want[i]).norm(), 1e-9 * (1 + want[i].norm() + terms[i]));
    }
    std::vector<Vec3> hv_y, want_y(p.points.size(), Vec3::Zero());
    for (const auto& [ab, block] : serial_h) want_y[ab.first][1] += block(1, 1) * v[ab.second][1];
    h.multiply(v, hv_y, 1);
    for (size_t i = 0; i < v.size(); ++i)
        EXPECT_LT((hv_y[i] - want_y[i]).norm(), 1e-5 * (1 + want_y[i].norm()));
}

}  // namespace

TEST(Assembly, ParallelSumsEqualTheSerialSumsAndTheHessianIsTheirUpperTriangle) {
    const Problem p = test_support::displaced_grid_problem(8, 0.4, 2);
    const Assembly a(p);
    EXPECT_GT(a.chunks(), 1);
    EXPECT_GT(a.colours(), 1);
    expect_assembly_matches_serial_sums(p, a);
}

TEST(Assembly, HexesSplitBetweenChunksPlainTetsAndCoincidingNodesAssembleAlike) {
    // Chunks of 12 elements cut every other hex's corner tets in two (assembled tet by tet);
    // plain tets follow the hexes; one hex has two nodes merged (both its blocks between them
    // land on the diagonal), and the vertex ids are shuffled so that lower ids come second.
    Problem p = test_support::displaced_grid_problem(4, 0.3, 5);
    std::mt19937 rng(7);
    std::vector<Id> shuffled(p.points.size());
    for (size_t v = 0; v < shuffled.size(); ++v) shuffled[v] = Id(v);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    Problem q = p;
    for (size_t v = 0; v < shuffled.size(); ++v) {
        q.points[shuffled[v]] = p.points[v];
        q.kinds[shuffled[v]] = p.kinds[v];
    }
    for (auto& h : q.hexes)
        for (Id& v : h) v = shuffled[v];
    std::array<Id, 8> merged = q.hexes[5];
    merged[6] = merged[7];
    q.add_hex(merged, Vec3(1.0, 0.8, 1.2));
    for (size_t h = 0; h < 20; h += 3) {
        const auto& n = q.hexes[h];
        q.tets.push_back({n[0], n[1], n[3], n[4]});
        q.targets.push_back(regular_tet_target(1.0));
    }
    const Assembly a(q, 12);
    expect_assembly_matches_serial_sums(q, a);
}

TEST(Assembly, EqualWeightsScaleEveryTetToAUnitTarget) {
    // Hexes of box targets from 0.01 to 2.4 across (split between chunks or not) and plain
    // tets: with equal weights every sum is that of the tets weighed 1/6 each.
    Problem p = test_support::displaced_grid_problem(4, 0.3, 5);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> size(0.01, 2.4);
    for (Vec3& e : p.hex_edges) e = Vec3(size(rng), size(rng), size(rng));
    for (size_t h = 0; h < 20; h += 3) {
        const auto& n = p.hexes[h];
        p.tets.push_back({n[0], n[1], n[3], n[4]});
        p.targets.push_back(regular_tet_target(0.05 * double(h + 1)));
    }
    const EnergyParams equal{0.8, 0.1, true};
    expect_assembly_matches_serial_sums(p, Assembly(p, 12), equal);
    expect_assembly_matches_serial_sums(p, Assembly(p), equal);
    // A hex and the same hex 1000 times smaller (target and nodes): the same energy with equal
    // weights, 1e9 times less by volume.
    Problem big, small;
    big.points = test_support::displaced_grid_problem(1, 0, 1).points;
    big.kinds.assign(big.points.size(), VertexKind::interior);
    big.points[6] += Vec3(-0.9, -0.8, -1.3);  // inverted corners
    big.add_hex({0, 1, 3, 2, 4, 5, 7, 6}, Vec3(1, 1, 1));
    small = big;
    for (Vec3& x : small.points) x *= 1e-3;
    small.hex_edges[0] *= 1e-3;
    const double e_big = Assembly(big).energy(big.points, equal);
    EXPECT_NEAR(Assembly(small).energy(small.points, equal), e_big, 1e-9 * e_big);
    const EnergyParams by_volume{0.8, 0.1};
    EXPECT_NEAR(Assembly(small).energy(small.points, by_volume),
                1e-9 * Assembly(big).energy(big.points, by_volume), 1e-18 * e_big);
    EXPECT_GT(Assembly(big).stats(big.points).inverted, 0);
}

TEST(Assembly, SurfaceTrianglesAssembleLikeTheSerialSumsAndCountInTheStats) {
    // The 4 corner triangles of every quad of the face z = 0 (seen from below: the normal
    // field points to -z, tilted differently at every vertex), its nodes moved in the plane;
    // chunks of 12 elements mix triangles with the hexes' corner tets.
    Problem p = test_support::displaced_grid_problem(4, 0.3, 6);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.25, 0.25);
    const auto id = [](int i, int j) { return Id(i + 5 * j); };
    for (int j = 1; j < 4; ++j)
        for (int i = 1; i < 4; ++i) p.points[id(i, j)] += Vec3(u(rng), u(rng), 0);
    p.surface_normal = [](Id, const Vec3& x) {
        return Vec3(0.2 * std::sin(3 * x[0]), 0.2 * std::cos(2 * x[1]), -1);
    };
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            // Counter-clockwise from -z: (i, j) -> (i, j + 1) -> (i + 1, j + 1) -> (i + 1, j).
            const std::array<Id, 4> quad = {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)};
            for (int c = 0; c < 4; ++c) {
                p.triangles.push_back({quad[c], quad[(c + 1) % 4], quad[(c + 3) % 4]});
                p.triangle_targets.push_back(rectangle_corner_target(1, 1));
            }
        }
    const Assembly a(p, 12);
    expect_assembly_matches_serial_sums(p, a);
    // A folded triangle counts as inverted, and only the triangles see it (fixed hexes' z = 0
    // nodes do not move out of the plane).
    const ElementStats before = a.stats(p.points);
    EXPECT_EQ(before.inverted, 0);
    std::swap(p.points[id(2, 2)], p.points[id(2, 3)]);
    Id folded = 0;
    for (Id r = 0; r < Id(p.triangles.size()); ++r)
        folded += !(p.det(p.points, p.first_triangle() + r) > 0);
    EXPECT_GT(folded, 0);
    Id folded_tets = 0;
    for (Id e = 0; e < p.first_triangle(); ++e) folded_tets += !(p.det(p.points, e) > 0);
    EXPECT_EQ(a.stats(p.points).inverted, folded + folded_tets);
}

TEST(Assembly, TrianglesAloneAssembleLikeTheSerialSums) {
    // A 3 x 3 patch of quads in the plane z = 0, each cut into its 4 corner triangles (pairs
    // across a quad's diagonal that no tet has), nodes moved in the plane, one triangle
    // folded; the normal field tilted from place to place.
    Problem p;
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            p.points.push_back(Vec3(i + u(rng), j + u(rng), 0));
            p.kinds.push_back(VertexKind::slip);
        }
    std::swap(p.points[5], p.points[6]);
    p.surface_normal = [](Id, const Vec3& x) { return Vec3(0.1 * x[1], -0.2 * x[0], 1); };
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            const std::array<Id, 4> q = {Id(i + 4 * j), Id(i + 1 + 4 * j), Id(i + 1 + 4 * (j + 1)),
                                         Id(i + 4 * (j + 1))};
            for (int c = 0; c < 4; ++c) {
                p.triangles.push_back({q[c], q[(c + 1) % 4], q[(c + 3) % 4]});
                p.triangle_targets.push_back(rectangle_corner_target(1, 1.2));
            }
        }
    const Assembly a(p, 5);
    EXPECT_GT(a.stats(p.points).inverted, 0);
    expect_assembly_matches_serial_sums(p, a);
    // Where grad u is not finite the energy is NaN (a line search rejects the step), and a
    // problem that starts so is refused with the place named; an interior vertex on a
    // triangle is refused (it would have no stiffness along n).
    Problem nan_normal = p;
    nan_normal.kinds.assign(p.points.size(), VertexKind::fixed);
    nan_normal.surface_normal = [](Id, const Vec3& x) {
        return x[0] > 2.5 && x[1] > 2.5 ? Vec3(NAN, 0, 1) : Vec3(0, 0, 1);
    };
    EXPECT_TRUE(std::isnan(Assembly(nan_normal).energy(nan_normal.points, {0.8, 0.1})));
    try {
        check_constraints(nan_normal);
        ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "no normal of u = 0 at the surface triangle with centroid ("),
                  std::string::npos)
            << e.what();
    }
    p.kinds.assign(p.points.size(), VertexKind::fixed);
    p.kinds[0] = VertexKind::interior;
    EXPECT_THROW(check_constraints(p), std::invalid_argument);
}

TEST(Assembly, HeldQuadsAddTheGapOfTheirCentresToEverySum) {
    // The quads of the face z = 0 held to a sphere of radius 10 below it (u its signed
    // distance, the unit normal its gradient), with a quad that is not a face of any hex
    // (nodes of two hex layers: pairs the tets do not have), hexes in chunks of 5.
    Problem p = test_support::displaced_grid_problem(3, 0.3, 3);
    const Vec3 centre(1.5, 1.5, -10);
    p.surface_value = [centre](const Vec3& x) { return (x - centre).norm() - 10; };
    p.surface_normal = [centre](Id, const Vec3& x) { return x - centre; };
    const auto id = [](int i, int j, int k) { return Id(i + 4 * (j + 4 * k)); };
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            p.held_quads.push_back(
                {{id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0)},
                 0.5 + i,
                 2.0 + j});
    p.held_quads.push_back({{id(1, 1, 1), id(2, 1, 1), id(2, 2, 2), id(1, 2, 2)}, 3, 1});
    for (int j = 1; j < 3; ++j)
        for (int i = 1; i < 3; ++i) p.points[id(i, j, 0)].z() += 0.1 * (i - j);
    const Assembly a(p, 5);
    expect_assembly_matches_serial_sums(p, a);
    EnergyParams equal{0.8, 0.1};
    equal.equal_weights = true;
    expect_assembly_matches_serial_sums(p, a, equal);
    // The gradient is the exact one: finite differences of the energy agree.
    expect_gradient_matches_finite_differences(p, a, equal,
                                               {id(1, 1, 0), id(2, 2, 2), id(1, 2, 1)});
    // The term is what it says: a quad on u = 0 costs nothing, one at height 0.2 its weight
    // times 0.04.
    Problem flat = test_support::displaced_grid_problem(1, 0, 1);
    flat.surface_value = [](const Vec3& y) { return y.z() - 0.2; };
    flat.surface_normal = [](Id, const Vec3&) { return Vec3(0, 0, 1); };
    const double shape = Assembly(flat).energy(flat.points, {0.8, 0});
    flat.held_quads.push_back({{0, 1, 3, 2}, 5, 7});
    EXPECT_NEAR(Assembly(flat).energy(flat.points, {0.8, 0}), shape + 5 * 0.04, 1e-12);
    flat.surface_value = [](const Vec3& y) { return y.z(); };
    EXPECT_NEAR(Assembly(flat).energy(flat.points, {0.8, 0}), shape, 1e-12);
    // Without u the quads cannot be held: refused.
    flat.surface_value = nullptr;
    EXPECT_THROW(Assembly{flat}, std::invalid_argument);
}

TEST(Assembly, HessianProductsRunInParallelWhenTheRowsAreMany) {
    // 31^3 nodes: the products cut the rows into ranges of several colours.
    const Problem p = test_support::displaced_grid_problem(30, 0.3, 4);
    const Assembly a(p);
    BlockMatrix h = a.empty_hessian();
    std::vector<Vec3> g;
    a.hessian(p.points, {0.8, 0.1}, g, h);
    EXPECT_GT(h.range_order.size(), 4u);
    EXPECT_GT(h.colour_start.size(), 2u);
    EXPECT_LT(h.colour_start.size(), h.range_order.size());
    std::vector<Vec3> v(p.points.size());
    for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3(std::sin(i), std::cos(3.0 * i), 0.5);
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Vec3> out;
        h.multiply(v, out);
        return out;
    };
    const std::vector<Vec3> one = run(1), two = run(2);
    EXPECT_EQ(one, two);  // bitwise
    // Against a serial product over the stored blocks, in double (the product runs in single
    // precision, as the blocks are stored).
    std::vector<Vec3> want(v.size(), Vec3::Zero());
    for (Id r = 0; r < h.rows(); ++r)
        for (Id m = h.row_start[r]; m < h.row_start[r + 1]; ++m) {
            const Mat3 b = h.block[m].cast<double>();
            want[r] += b * v[h.col[m]];
            if (h.col[m] != r) want[h.col[m]] += b.transpose() * v[r];
        }
    double scale = 0;
    for (const Vec3& w : want) scale = std::max(scale, w.norm());
    for (size_t i = 0; i < v.size(); ++i) EXPECT_LT((one[i] - want[i]).norm(), 1e-5 * scale);
}

TEST(Assembly, ResultsAreBitwiseIdenticalForOneAndTwoThreads) {
    const Problem p = test_support::displaced_grid_problem(6, 0.5, 3);
    const Assembly a(p);
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<Vec3> g;
        const double f = a.gradient(p.points, {0.8, 0.1}, g);
        return std::make_pair(f, g);
    };
    const auto one = run(1), two = run(2);
    EXPECT_EQ(one.first, two.first);
    EXPECT_EQ(one.second, two.second);
}

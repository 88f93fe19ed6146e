// Quality metrics on grids whose answers are known in closed form, and exact validity.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/reference_hex.h"
#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/cell_quality.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "hexmesh/quality/validity.h"
#include "tests/hand_grids.h"

namespace hexmesh {
namespace {

constexpr double pi = 3.14159265358979323846;

// Single-block tensor-product grid with nodes at (xs[i], ys[j], zs[k]).
HexMesh tensor_grid(const std::vector<double>& xs, const std::vector<double>& ys,
                    const std::vector<double>& zs) {
    BlockGrid grid;
    Block block;
    block.nodes = {int(xs.size()), int(ys.size()), int(zs.size())};
    for (double z : zs)
        for (double y : ys)
            for (double x : xs) {
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.emplace_back(x, y, z);
            }
    grid.blocks.push_back(block);
    return to_hex_mesh(grid);
}

std::vector<double> uniform(int cells, double h) {
    std::vector<double> v;
    for (int i = 0; i <= cells; ++i) v.push_back(i * h);
    return v;
}

std::array<Vec3, 8> unit_cube() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
            Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

HexMesh single_hex(const std::array<Vec3, 8>& p) {
    HexMesh mesh;
    mesh.points.assign(p.begin(), p.end());
    for (Id i = 0; i < 8; ++i) mesh.hexes.push_back(i);
    return mesh;
}

TEST(ExactOrientation, PositiveMeansPositiveDeterminantOnUnitCube) {
    const auto p = unit_cube();
    for (const auto& [c, a, b, d] : hex_corner_tets) {
        EXPECT_EQ(exact_orientation(p[c], p[a], p[b], p[d]), 1);
        EXPECT_EQ(exact_orientation(p[c], p[b], p[a], p[d]), -1);  // odd permutation
    }
    EXPECT_EQ(exact_orientation(p[0], p[1], p[2], p[3]), 0);  // the bottom face is flat
    EXPECT_EQ(count_inverted_corner_tets(p), 0);
}

TEST(Quality, UniformCubesArePerfect) {
    const HexMesh mesh = tensor_grid(uniform(4, 0.5), uniform(3, 0.5), uniform(2, 0.5));
    const QualityReport q = measure_quality(mesh);
    EXPECT_EQ(q.cells, 24);
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_EQ(q.inverted_cells, 0);
    EXPECT_EQ(q.min_scaled_jacobian, 1.0);
    EXPECT_EQ(q.mean_scaled_jacobian, 1.0);
    EXPECT_NEAR(q.max_non_orthogonality_deg, 0.0, 1e-5);
    EXPECT_LT(q.max_skewness, 1e-12);
    EXPECT_NEAR(q.max_aspect_ratio, 1.0, 1e-12);
    EXPECT_NEAR(q.max_volume_ratio, 1.0, 1e-12);
    EXPECT_NEAR(q.min_volume, 0.125, 1e-15);
}

TEST(Quality, AspectRatioOfFourToOneCellsIsFour) {
    const HexMesh mesh = tensor_grid(uniform(3, 4.0), uniform(2, 1.0), uniform(2, 1.0));
    const QualityReport q = measure_quality(mesh);
    EXPECT_NEAR(q.max_aspect_ratio, 4.0, 1e-12);
    EXPECT_NEAR(q.min_volume, 4.0, 1e-12);
    EXPECT_EQ(q.min_scaled_jacobian, 1.0);  // a box is perfect for the scaled Jacobian
}

TEST(Quality, ShearedGridNonOrthogonalityIsAtanOfShear) {
    const double s = 0.3, h = 0.25;
    HexMesh mesh = tensor_grid(uniform(4, h), uniform(4, h), uniform(3, h));
    for (Vec3& p : mesh.points) p[0] += s * p[1];
    const QualityReport q = measure_quality(mesh);
    EXPECT_NEAR(q.max_non_orthogonality_deg, std::atan(s) * 180 / pi, 1e-9);
    EXPECT_NEAR(q.min_scaled_jacobian, 1 / std::sqrt(1 + s * s), 1e-14);
    EXPECT_NEAR(q.min_volume, h * h * h, 1e-15);
    // Internal faces are centred on the neighbour line; a wall face y = 0 is offset s h / 2
    // along the wall from its owner centre, over a half-width h / 2: skewness s.
    EXPECT_NEAR(q.max_skewness, s, 1e-12);
    EXPECT_EQ(q.inverted_cells, 0);
}

TEST(Quality, GeometricStretchingGivesVolumeRatioR) {
    const double r = 1.2;
    std::vector<double> xs{0};
    for (int i = 0; i < 6; ++i) xs.push_back(xs.back() + 0.1 * std::pow(r, i));
    const HexMesh mesh = tensor_grid(xs, uniform(2, 0.1), uniform(2, 0.1));
    const QualityReport q = measure_quality(mesh);
    EXPECT_NEAR(q.max_volume_ratio, r, 1e-12);
    EXPECT_NEAR(q.min_volume, 0.001, 1e-15);
    EXPECT_NEAR(q.max_non_orthogonality_deg, 0.0, 1e-5);
}

TEST(Validity, CornerPushedThroughOppositeFaceIsInverted) {
    // Two unit cubes side by side; node 5 of the second (not shared with the first) is
    // pushed from (2, 0, 1) to below the bottom face.
    HexMesh mesh = tensor_grid(uniform(2, 1.0), uniform(1, 1.0), uniform(1, 1.0));
    mesh.points[mesh.node(1, 5)] = Vec3(1.5, 0.5, -0.5);
    const auto dets = corner_determinants(mesh.corners(1));
    int negative = 0;
    for (double d : dets) negative += d < 0;
    ASSERT_GT(negative, 0);
    EXPECT_EQ(count_inverted_corner_tets(mesh.corners(1)), negative);
    EXPECT_EQ(count_inverted_corner_tets(mesh.corners(0)), 0);

    const InversionCount n = count_inversions(mesh);
    EXPECT_EQ(n.corner_tets, negative);
    EXPECT_EQ(n.cells, 1);
    EXPECT_EQ(find_inverted_cells(mesh), std::vector<Id>{1});
    const QualityReport q = measure_quality(mesh);
    EXPECT_EQ(q.inverted_corner_tets, negative);
    EXPECT_EQ(q.inverted_cells, 1);
    EXPECT_LT(q.min_scaled_jacobian, 0.0);
}

TEST(Validity, ExactlyFlatCornerTetIsInvertedEvenWhenFloatSaysPositive) {
    // A right-handed random frame o + [u v w] maps the unit cube to a hex; node 4 is moved to
    // o - (u + v) / 2, the image of (-1/2, -1/2, 0): corner tet 0 = (0, 1, 3, 4) becomes exactly
    // flat while the 7 other corner tets stay positive. u, v are even integer vectors, so every
    // coordinate is exact, but the rounded floating-point determinant of the flat tet is often
    // not 0: look for a case where it is > 0, which a floating-point check would accept.
    std::mt19937_64 rng(12345);
    std::uniform_int_distribution<std::int64_t> coord(-(1 << 20), 1 << 20);
    auto even_vec = [&] { return Vec3(2 * coord(rng), 2 * coord(rng), 2 * coord(rng)); };
    bool found = false;
    for (int attempt = 0; attempt < 10000 && !found; ++attempt) {
        const Vec3 o = even_vec(), u = even_vec(), v = even_vec(), w = even_vec();
        if (u.dot(v.cross(w)) <= 0) continue;
        std::array<Vec3, 8> p = {o,     o + u,     o + u + v,     o + v,
                                 o + w, o + u + w, o + u + v + w, o + v + w};
        p[4] = o - 0.5 * (u + v);
        const auto dets = corner_determinants(p);
        if (dets[0] <= 0) continue;
        found = true;
        for (double d : dets) EXPECT_GT(d, 0.0);  // floating point sees a valid hex
        EXPECT_EQ(exact_orientation(p[0], p[1], p[3], p[4]), 0);
        EXPECT_EQ(count_inverted_corner_tets(p), 1);
        const InversionCount n = count_inversions(single_hex(p));
        EXPECT_EQ(n.corner_tets, 1);
        EXPECT_EQ(n.cells, 1);
        EXPECT_EQ(measure_quality(single_hex(p)).inverted_cells, 1);
    }
    ASSERT_TRUE(found) << "no rounding-positive flat tet found; the test needs another seed";
}

TEST(Quality, ParallelResultsAreDeterministicAndMatchPerCellValues) {
    HexMesh mesh = tensor_grid(uniform(40, 1.0), uniform(30, 1.0), uniform(20, 1.0));
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (Vec3& p : mesh.points) p += Vec3(jitter(rng), jitter(rng), jitter(rng));

    const std::vector<double> sj = scaled_jacobians(mesh);
    ASSERT_EQ(Id(sj.size()), mesh.num_cells());
    double min_sj = 1e300;
    for (Id c = 0; c < mesh.num_cells(); ++c) {
        EXPECT_EQ(sj[c], hex_scaled_jacobian(mesh.corners(c)));
        min_sj = std::min(min_sj, sj[c]);
    }
    const QualityReport a = measure_quality(mesh), b = measure_quality(mesh);
    EXPECT_EQ(a.min_scaled_jacobian, min_sj);
    EXPECT_EQ(a.mean_scaled_jacobian, b.mean_scaled_jacobian);  // bitwise: fixed reduction
    EXPECT_EQ(a.max_skewness, b.max_skewness);
    EXPECT_EQ(a.max_non_orthogonality_deg, b.max_non_orthogonality_deg);
    EXPECT_GT(a.max_non_orthogonality_deg, 0.0);
    EXPECT_GT(a.max_volume_ratio, 1.0);
}

// The histograms count every cell and internal face in the right bin, and the worst cells
// are the lowest scaled Jacobians in order: the same as a mesh and block by block.
TEST(Quality, HistogramsAndWorstCellsCountEveryCell) {
    const int n = 12;
    BlockGrid grid;
    Block block;
    block.nodes = {n + 1, n + 1, n + 1};
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.emplace_back(i + jitter(rng), j + jitter(rng), k + jitter(rng));
            }
    grid.blocks.push_back(block);
    const HexMesh mesh = to_hex_mesh(grid);
    const std::vector<double> sj = scaled_jacobians(mesh);
    Histogram expected = scaled_jacobian_bins();
    for (double v : sj) expected.add(v);
    std::vector<Id> order(sj.size());
    for (Id c = 0; c < Id(order.size()); ++c) order[c] = c;
    std::stable_sort(order.begin(), order.end(), [&](Id a, Id b) { return sj[a] < sj[b]; });

    for (const QualityReport& q : {measure_quality(mesh), measure_quality(grid)}) {
        EXPECT_EQ(q.scaled_jacobian_histogram.counts, expected.counts);
        EXPECT_EQ(q.scaled_jacobian_histogram.total(), q.cells);
        EXPECT_EQ(q.internal_faces, Id(3) * n * n * (n - 1));
        EXPECT_EQ(q.non_orthogonality_histogram.total(), q.internal_faces);
        // The highest non-empty bin holds the max non-orthogonality.
        const std::vector<Id>& bins = q.non_orthogonality_histogram.counts;
        const auto last = std::find_if(bins.rbegin(), bins.rend(), [](Id c) { return c > 0; });
        EXPECT_EQ(int(bins.rend() - last) - 1, int(q.max_non_orthogonality_deg / 10));
        ASSERT_EQ(q.worst_cells.size(), worst_cells_listed);
        for (std::size_t r = 0; r < worst_cells_listed; ++r) {
            EXPECT_EQ(q.worst_cells[r].cell, order[r]);
            EXPECT_EQ(q.worst_cells[r].scaled_jacobian, sj[order[r]]);
        }
        EXPECT_EQ(q.worst_cells[0].cell, q.worst_cell);
    }
}

// The report names its worst cell (the lowest id among equals) and that cell's centre, the
// same whether measured as a mesh or block by block.
TEST(Quality, TheWorstCellIsNamedWithItsCentre) {
    BlockGrid grid;
    Block block;
    block.nodes = {6, 5, 4};
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 6; ++i) {
                block.node_ids.push_back(Id(grid.points.size()));
                grid.points.emplace_back(i, j, k);
            }
    grid.blocks.push_back(block);
    grid.points[block.node(3, 2, 1)] +=
        Vec3(0.45, 0.4, 0.3);  // shears its 8 cells, (2, 1, 0) worst
    const HexMesh mesh = to_hex_mesh(grid);
    const std::vector<double> sj = scaled_jacobians(mesh);
    const Id worst = Id(std::min_element(sj.begin(), sj.end()) - sj.begin());
    EXPECT_LT(sj[worst], 0.9);
    const QualityReport a = measure_quality(mesh), b = measure_quality(grid);
    EXPECT_EQ(a.worst_cell, worst);
    EXPECT_EQ(b.worst_cell, worst);
    Vec3 mean = Vec3::Zero();
    for (const Vec3& p : mesh.corners(worst)) mean += p / 8;
    EXPECT_LT((a.worst_cell_centre - mean).norm(), 0.1);
    EXPECT_LT((b.worst_cell_centre - a.worst_cell_centre).norm(), 1e-12);
    EXPECT_EQ(measure_quality(HexMesh{}).worst_cell, -1);
}

TEST(Quality, FaceSharedByThreeCellsIsRejected) {
    HexMesh mesh = single_hex(unit_cube());
    for (int copy = 0; copy < 2; ++copy)
        for (Id i = 0; i < 8; ++i) mesh.hexes.push_back(i);
    EXPECT_THROW(measure_quality(mesh), std::invalid_argument);
}

// A cell from an optimized grid of a body with legs: its 8 corner tets are positive, but it is
// turned inside out at its centre (Verdict's centre frame -0.96, OpenFOAM volume < 0).
std::array<Vec3, 8> inside_out_cell() {
    return {Vec3(-0.141865, 0.190517, 0.212616), Vec3(-0.143186, 0.199647, 0.204166),
            Vec3(-0.158641, 0.160889, 0.142733), Vec3(-0.156454, 0.15972, 0.139122),
            Vec3(-0.143301, 0.190185, 0.211333), Vec3(-0.143869, 0.197249, 0.201958),
            Vec3(-0.146059, 0.159576, 0.147823), Vec3(-0.152377, 0.160523, 0.140178)};
}

TEST(SolverValidity, ACellInsideOutAtItsCentreIsRefusedThoughItsCornersArePositive) {
    HexMesh mesh = tensor_grid(uniform(2, 1.0), uniform(1, 1.0), uniform(1, 1.0));  // cells 0, 1
    const std::array<Vec3, 8> bad = inside_out_cell();
    const Id first = Id(mesh.points.size());
    mesh.points.insert(mesh.points.end(), bad.begin(), bad.end());
    for (Id i = 0; i < 8; ++i) mesh.hexes.push_back(first + i);  // cell 2, apart
    EXPECT_EQ(count_inverted_corner_tets(bad), 0);
    const QualityReport q = measure_quality(mesh);
    EXPECT_EQ(q.inverted_corner_tets, 0);
    EXPECT_GT(q.negative_pyramids, 0);
    EXPECT_EQ(q.nonpositive_volumes, 1);
    EXPECT_FALSE(q.solver_valid());
    EXPECT_EQ(find_refused_cells(mesh), std::vector<Id>{2});

    const QualityReport cubes =
        measure_quality(tensor_grid(uniform(2, 1.0), uniform(1, 1.0), uniform(1, 1.0)));
    EXPECT_TRUE(cubes.solver_valid());
    EXPECT_EQ(cubes.negative_pyramids + cubes.faces_over_90_deg + cubes.nonpositive_volumes, 0);
}

// A face of skewness over 4 (checkMesh fails it) with every cell check passed: the block pass and
// the unstructured pass count the same faces (the shared one and the two ends, each (2 / 2) / 0.2
// = 5 skewed), call the grid not valid and refuse both cells; upright, nothing is refused.
TEST(SolverValidity, FacesOfSkewnessOverFourAreRefusedWithTheirCells) {
    const BlockGrid grid = test::leaning_cells(2.0);
    const HexMesh mesh = to_hex_mesh(grid);
    for (const QualityReport& q : {measure_quality(grid), measure_quality(mesh)}) {
        EXPECT_EQ(q.inverted_corner_tets + q.negative_pyramids + q.nonpositive_volumes, 0);
        EXPECT_EQ(q.highly_skewed_faces, 3);
        EXPECT_NEAR(q.max_skewness, 5.0, 1e-9);
        EXPECT_FALSE(q.solver_valid());
    }
    EXPECT_EQ(find_refused_cells(mesh), (std::vector<Id>{0, 1}));
    const QualityReport upright = measure_quality(to_hex_mesh(test::leaning_cells(0.0)));
    EXPECT_EQ(upright.highly_skewed_faces, 0);
    EXPECT_TRUE(upright.solver_valid());
    EXPECT_TRUE(find_refused_cells(to_hex_mesh(test::leaning_cells(0.0))).empty());
}

// A cell 2000 times wider than it is thick: over checkMesh's aspect-ratio limit (1000), counted
// and noted, but valid for a solver; at 500 it is not counted.
TEST(SolverValidity, CellsOverTheAspectRatioLimitAreCountedNotRefused) {
    for (const double thickness : {0.0005, 0.002}) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& x : p) x.z() *= thickness;
        const HexMesh mesh = single_hex(p);
        const QualityReport q = measure_quality(mesh);
        const Id over = thickness < 0.001 ? 1 : 0;
        EXPECT_NEAR(q.max_aspect_ratio, 1 / thickness, 1e-6 / thickness);
        EXPECT_EQ(q.high_aspect_ratio_cells, over);
        EXPECT_EQ(aspect_ratio_note(q).empty(), over == 0);
        EXPECT_TRUE(q.solver_valid());
        EXPECT_TRUE(find_refused_cells(mesh).empty());
    }
    // A flat cell (volume 0) is over the limit too, as in checkMesh, but refused: no note that
    // solvers run on it.
    std::array<Vec3, 8> flat = unit_cube();
    for (Vec3& x : flat) x.z() = 0;
    const QualityReport q = measure_quality(single_hex(flat));
    EXPECT_GE(q.high_aspect_ratio_cells, 1);
    EXPECT_FALSE(q.solver_valid());
    EXPECT_EQ(aspect_ratio_note(q), "");
}

// solver_margin is positive exactly when the cell alone passes the solver's checks, on random
// cells (a unit cube's corners each moved up to 0.45 along each axis) of both kinds.
TEST(SolverValidity, TheMarginIsPositiveExactlyWhenTheSolverAcceptsTheCell) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.45, 0.45);
    int accepted = 0, refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& x : p) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
        const bool accepts = find_refused_cells(single_hex(p)).empty();
        EXPECT_EQ(solver_margin(p) > 0, accepts)
            << "trial " << trial << ", margin " << solver_margin(p);
        ++(accepts ? accepted : refused);
    }
    EXPECT_GT(accepted, 300);
    EXPECT_GT(refused, 300);
    EXPECT_LT(solver_margin(inside_out_cell()), 0);
    EXPECT_NEAR(solver_margin(unit_cube()), 0.5, 1e-12);  // centre half an edge inside each face
}

// solver_margins' 14 terms: the 8 corner scaled Jacobians (1 on a unit cube, as
// hex_frame_jacobians gives them on any cell) and the 6 faces' (0.5), whose smallest is
// solver_margin on every random cell of the test above.
TEST(SolverValidity, TheMarginsTermsAreTheCornersAndTheFaces) {
    const std::array<double, 14> cube = solver_margins(unit_cube());
    for (int k = 0; k < 14; ++k) EXPECT_NEAR(cube[k], k < 8 ? 1.0 : 0.5, 1e-12) << "term " << k;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.45, 0.45);
    for (int trial = 0; trial < 1000; ++trial) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& x : p) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
        const std::array<double, 14> terms = solver_margins(p);
        const std::array<double, 9> frames = hex_frame_jacobians(p);
        for (int k = 0; k < 8; ++k) EXPECT_NEAR(terms[k], frames[k + 1], 1e-12) << trial;
        EXPECT_EQ(*std::min_element(terms.begin(), terms.end()), solver_margin(p)) << trial;
    }
}

// Verdict scores a cell with a zero-length edge 1e30; the mean stays a mean of values in [-1, 1].
TEST(SolverValidity, ADegenerateCellDoesNotSwampTheMeanScaledJacobian) {
    std::array<Vec3, 8> p = unit_cube();
    p[6] = p[5];
    const QualityReport q = measure_quality(single_hex(p));
    EXPECT_EQ(q.min_scaled_jacobian, 1e30);
    EXPECT_LE(q.mean_scaled_jacobian, 1.0);
    EXPECT_FALSE(q.solver_valid());
}

}  // namespace
}  // namespace hexmesh

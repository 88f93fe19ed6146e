// Speed of the untangler's kernels (energy, gradient, Hessian) and of whole untangling runs.
#include <benchmark/benchmark.h>

#include "tests/untangle/grid_problem.h"
#include "untangle/assembly.h"
#include "untangle/untangle.h"

using namespace hexmesh;
using namespace hexmesh::untangle;

namespace {

// n^3 unit cubes split into corner tets, interior nodes displaced by up to `amplitude` cells
// (the untangler tests' grid, seed 1).
Problem displaced_grid(int n, double amplitude) {
    return test_support::displaced_grid_problem(n, amplitude, 1);
}

void BM_Energy(benchmark::State& state) {
    const Problem p = displaced_grid(int(state.range(0)), 0.3);
    const Assembly a(p);
    for (auto _ : state) benchmark::DoNotOptimize(a.energy(p.points, {0.8, 0.1}));
    state.counters["tets/s"] =
        benchmark::Counter(double(p.num_elements()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Energy)->Arg(20)->Unit(benchmark::kMillisecond);

void BM_Gradient(benchmark::State& state) {
    const Problem p = displaced_grid(int(state.range(0)), 0.3);
    const Assembly a(p);
    std::vector<Vec3> g;
    for (auto _ : state) benchmark::DoNotOptimize(a.gradient(p.points, {0.8, 0.1}, g));
    state.counters["tets/s"] =
        benchmark::Counter(double(p.num_elements()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Gradient)->Arg(20)->Unit(benchmark::kMillisecond);

void BM_Hessian(benchmark::State& state) {
    const Problem p = displaced_grid(int(state.range(0)), 0.3);
    const Assembly a(p);
    std::vector<Vec3> g;
    BlockMatrix h = a.empty_hessian();
    for (auto _ : state) benchmark::DoNotOptimize(a.hessian(p.points, {0.8, 0.1}, g, h));
    state.counters["tets/s"] =
        benchmark::Counter(double(p.num_elements()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Hessian)->Arg(20)->Unit(benchmark::kMillisecond);

// One product with the assembled Hessian (a CG iteration's main cost), on (n + 1)^3 nodes.
void BM_HessianProduct(benchmark::State& state) {
    const Problem p = displaced_grid(int(state.range(0)), 0.3);
    const Assembly a(p);
    std::vector<Vec3> g, v(p.points.size(), Vec3(0.3, -0.2, 0.1)), out;
    BlockMatrix h = a.empty_hessian();
    a.hessian(p.points, {0.8, 0.1}, g, h);
    for (auto _ : state) {
        h.multiply(v, out);
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["rows/s"] =
        benchmark::Counter(double(h.rows()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["MB"] =
        double(h.block.size() * sizeof(HessianBlock) + h.col.size() * sizeof(int32_t)) / 1e6;
}
BENCHMARK(BM_HessianProduct)->Arg(64)->Unit(benchmark::kMillisecond);

void BM_UntangleStress(benchmark::State& state) {
    for (auto _ : state) {
        Problem p = displaced_grid(int(state.range(0)), 2.0);
        UntangleOptions o;
        o.untangle_solver.method = Method(state.range(1));
        o.optimize_solver.method = Method::block_diagonal;
        const UntangleResult r = untangle_and_optimize(p, o);
        state.counters["inverted_before"] = double(r.inverted_before);
        state.counters["inverted_after"] = double(r.inverted_after);
    }
}
BENCHMARK(BM_UntangleStress)
    ->Args({10, int(Method::newton_cg)})
    ->Args({10, int(Method::coordinate_split)})
    ->Args({10, int(Method::lbfgs)})
    ->Args({32, int(Method::newton_cg)})  // 32 768 hexes, as large as the public sets' 30 k
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

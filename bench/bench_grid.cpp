// Speed of the initial O-H grid of a sphere and of the quality report, by grid size.
#include <benchmark/benchmark.h>

#include "hexmesh/quality/block_quality.h"
#include "hexmesh/quality/mesh_quality.h"
#include "surface/analytic.h"
#include "volume/o_h_grid.h"

using namespace hexmesh;

namespace {

OHGridOptions options(int n) {
    OHGridOptions o;
    o.cells_per_edge = n;
    o.wall_cells = n / 2;
    o.wall_layers = {0.2 / n, 1.15, 10};
    return o;
}

void BM_OHGridSphere(benchmark::State& state) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    Id cells = 0;
    for (auto _ : state) {
        const BlockGrid grid = make_o_h_grid(sphere, options(int(state.range(0))));
        cells = grid.num_cells();
        benchmark::DoNotOptimize(grid.points.data());
    }
    state.counters["cells"] = double(cells);
    state.counters["cells/s"] =
        benchmark::Counter(double(cells), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_OHGridSphere)->Arg(32)->Arg(64)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_QualityReport(benchmark::State& state) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    const HexMesh mesh = to_hex_mesh(make_o_h_grid(sphere, options(int(state.range(0)))));
    for (auto _ : state) benchmark::DoNotOptimize(measure_quality(mesh));
    state.counters["cells"] = double(mesh.num_cells());
    state.counters["cells/s"] =
        benchmark::Counter(double(mesh.num_cells()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_QualityReport)->Arg(32)->Arg(64)->Arg(100)->Unit(benchmark::kMillisecond);

// The same report read from the blocks (no unstructured copy, faces matched structurally).
void BM_QualityReportBlocks(benchmark::State& state) {
    const Sphere sphere(Vec3::Zero(), 1.0);
    const BlockGrid grid = make_o_h_grid(sphere, options(int(state.range(0))));
    for (auto _ : state) benchmark::DoNotOptimize(measure_quality(grid));
    state.counters["cells"] = double(grid.num_cells());
    state.counters["cells/s"] =
        benchmark::Counter(double(grid.num_cells()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_QualityReportBlocks)->Arg(32)->Arg(64)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

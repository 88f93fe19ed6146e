// Signed distance field build time (OpenVDB mesh-to-volume) against triangle count.
// Sphere surfaces of 10k, 100k and 1M triangles at 256 voxels across (voxel = 2 / 256);
// closed surfaces are signed by flood fill, the "open" runs (a few facets removed) by the
// winding number. Counters: active voxels and the tree's memory.
#include <benchmark/benchmark.h>

#include "surface/mesh_sdf.h"
#include "tests/surface/sample_surfaces.h"

namespace {

using namespace hexmesh;

// 2 lon (lat - 1) triangles: 10000, 99856, 1000000.
TriangleSurface sphere_of(int64_t triangles) {
    if (triangles <= 10000) return test::uv_sphere(Vec3::Zero(), 1.0, 100, 51);
    if (triangles <= 100000) return test::uv_sphere(Vec3::Zero(), 1.0, 316, 159);
    return test::uv_sphere(Vec3::Zero(), 1.0, 1000, 501);
}

void run(benchmark::State& state, SdfSign sign, bool open) {
    TriangleSurface surface = sphere_of(state.range(0));
    if (open) surface.triangles.resize(surface.triangles.size() - 5);  // 5 facets at the pole
    MeshSdfOptions options;
    options.resolution = 256;
    options.sign = sign;
    double voxels = 0, bytes = 0;
    for (auto _ : state) {
        const MeshSdf sdf(surface, options);
        voxels = double(sdf.active_voxels());
        bytes = double(sdf.memory_bytes());
    }
    state.counters["triangles"] = double(surface.triangles.size());
    state.counters["active_voxels"] = voxels;
    state.counters["memory_MB"] = bytes / 1e6;
}

void BM_SdfClosed(benchmark::State& state) {
    run(state, SdfSign::flood_fill, false);
}
void BM_SdfOpenWinding(benchmark::State& state) {
    run(state, SdfSign::winding_number, true);
}

BENCHMARK(BM_SdfClosed)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3)
    ->UseRealTime();
BENCHMARK(BM_SdfOpenWinding)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

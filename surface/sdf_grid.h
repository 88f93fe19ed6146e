// The voxel grid behind MeshSdf: narrow-band distances to a triangle surface, built by
// OpenVDB in its own module (hexmesh_openvdb, surface/openvdb_grid.cpp) that MeshSdf loads on
// first use. OpenVDB's ~70 000 symbol relocations cost about 40 ms at every program start:
// programs that never build a mesh SDF (untangle, analytic bodies) do not load it.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

// What to build: voxel edge and origin (world = origin + voxel * index), band half-widths in
// voxels, and the sign: the winding number (`winding`, > 1/2 inside) at the band voxels when
// given, else OpenVDB's exterior flood fill. The winding number is computed on this side
// (surface/winding_number.h) and handed over, so the module needs no hexmesh symbol from the
// program that loads it (it is linked with --no-undefined).
struct SdfGridSpec {
    double voxel = 0;
    Vec3 origin = Vec3::Zero();
    double exterior_band = 3, interior_band = 3;
    std::function<double(const Vec3&)> winding;  // empty: flood fill
};

class SdfGrid {
  public:
    virtual ~SdfGrid() = default;
    // The values at the voxels (i + a, j + b, k + c), a, b, c in {0, 1}, entry a + 2 b + 4 c
    // (the band's constant where a voxel is not active). Safe to call concurrently.
    virtual void corner_values(int i, int j, int k, double (&values)[8]) const = 0;
    // Index box of the active voxels (lo, hi inclusive); lo > hi when there is none.
    virtual std::array<int, 6> active_box() const = 0;
    virtual long long active_voxels() const = 0;
    virtual size_t memory_bytes() const = 0;
    // Writes the grid (named "sdf", a level set) to an OpenVDB .vdb file.
    virtual void write_vdb(const std::string& path) const = 0;
};

// Builds the grid of `surface` (OpenVDB's mesh-to-volume conversion, then the sign), in the
// module; loads the module on first call. Throws std::runtime_error naming the module when it
// cannot be loaded; OpenVDB's own errors (std::exception) pass through the module's C entry
// point unchanged (GCC unwinds through it).
std::unique_ptr<SdfGrid> build_sdf_grid(const TriangleSurface& surface, const SdfGridSpec& spec);

}  // namespace hexmesh

// The module's entry point (C linkage, so the loader finds it by name).
extern "C" hexmesh::SdfGrid* hexmesh_build_sdf_grid(const hexmesh::TriangleSurface& surface,
                                                    const hexmesh::SdfGridSpec& spec);

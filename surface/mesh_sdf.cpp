#include "surface/mesh_sdf.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "hexmesh/core/memory_limit.h"
#include "surface/sdf_grid.h"
#include "surface/winding_number.h"

namespace hexmesh {
namespace {

// Distance from p to the box (0 inside it).
double distance_to_box(const Box3& box, const Vec3& p) {
    return (box.lo - p).cwiseMax(p - box.hi).cwiseMax(0.0).norm();
}

bool has_boundary_edges(const TriangleSurface& s) {
    for (const auto& [edge, n] : edge_uses(s.triangles))
        if (n == 1) return true;
    return false;
}

using Builder = SdfGrid* (*)(const TriangleSurface&, const SdfGridSpec&);

// The module's entry point: the module next to this library (the build tree keeps them
// together), else wherever the dynamic loader finds it. Loaded once, kept loaded.
Builder load_builder() {
    static const Builder builder = [] {
        std::string tried;
        Dl_info self{};
        // The entry point of the module at `path`, or nullptr with the reason added to `tried`.
        const auto entry = [&tried](const std::string& path) -> Builder {
            if (void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
                if (void* symbol = dlsym(module, "hexmesh_build_sdf_grid"))
                    return reinterpret_cast<Builder>(symbol);
                tried += std::string(dlerror()) + "; ";
                dlclose(module);
                return nullptr;
            }
            tried += std::string(dlerror()) + "; ";
            return nullptr;
        };
        if (dladdr(reinterpret_cast<void*>(&load_builder), &self) && self.dli_fname) {
            const std::filesystem::path dir = std::filesystem::path(self.dli_fname).parent_path();
            if (const Builder b = entry((dir / HEXMESH_OPENVDB_MODULE).string())) return b;
        }
        if (const Builder b = entry(HEXMESH_OPENVDB_MODULE)) return b;
        throw std::runtime_error("cannot load the OpenVDB module " HEXMESH_OPENVDB_MODULE
                                 " that builds signed distance fields of surfaces: " +
                                 tried);
    }();
    return builder;
}

}  // namespace

std::unique_ptr<SdfGrid> build_sdf_grid(const TriangleSurface& surface, const SdfGridSpec& spec) {
    return std::unique_ptr<SdfGrid>(load_builder()(surface, spec));
}

struct MeshSdf::Grid {
    std::unique_ptr<SdfGrid> grid;
    Vec3 origin;
    double voxel = 0;
    double exterior = 0;  // band half-widths, geometry units
    double interior = 0;
    Box3 band_box;  // world box of the active voxels
    bool by_winding = false;
};

MeshSdf::MeshSdf(const TriangleSurface& surface, const MeshSdfOptions& options)
    : grid_(std::make_unique<Grid>()) {
    if (surface.triangles.empty()) throw std::invalid_argument("MeshSdf: empty surface");
    if (!(options.feature_angle >= 0 && options.feature_angle <= 180))
        throw std::invalid_argument("MeshSdf: feature angle must lie in [0, 180] degrees");
    if (!(options.exterior_band >= 1 && options.interior_band >= 1))
        throw std::invalid_argument("MeshSdf: band half-widths must be at least 1 voxel");
    bounds_ = surface_bounds(surface);
    const double extent = bounds_.size().maxCoeff();
    double voxel = options.voxel_size;
    if (voxel <= 0) {
        if (options.resolution < 2) throw std::invalid_argument("MeshSdf: resolution must be >= 2");
        voxel = extent / options.resolution;
    }
    if (!(voxel > 0) || !std::isfinite(voxel) || extent / voxel > 1e5)
        throw std::invalid_argument(
            "the voxel size must be positive and at least 1e-5 of "
            "the surface's extent");

    const double limit = options.max_bytes > 0 ? options.max_bytes : memory_limit();
    const double needed =
        sdf_memory_estimate(surface, voxel, options.exterior_band, options.interior_band);
    if (needed > limit)
        throw std::invalid_argument(
            fmt::format("a distance field of voxel size {:.3g} ({:.0f} voxels along the longest "
                        "side) would take about "
                        "{:.3g} GB, more than the limit of {:.3g} GB: use a larger voxel size (or "
                        "--max-memory)",
                        voxel, extent / voxel, needed / 1e9, limit / 1e9));

    Grid& g = *grid_;
    g.voxel = voxel;
    g.origin = bounds_.lo;
    g.exterior = options.exterior_band * voxel;
    g.interior = options.interior_band * voxel;
    g.by_winding = options.sign == SdfSign::winding_number ||
                   (options.sign == SdfSign::automatic && has_boundary_edges(surface));
    std::optional<WindingNumber> winding;
    SdfGridSpec spec{voxel, g.origin, options.exterior_band, options.interior_band, {}};
    if (g.by_winding) {
        winding.emplace(surface);
        spec.winding = [&winding](const Vec3& p) { return (*winding)(p); };
    }
    g.grid = build_sdf_grid(surface, spec);

    const std::array<int, 6> box = g.grid->active_box();
    if (box[0] > box[3])
        throw std::invalid_argument("the distance field has no voxel near the surface");
    for (int a = 0; a < 3; ++a) {
        g.band_box.lo[a] = g.origin[a] + voxel * box[a];
        g.band_box.hi[a] = g.origin[a] + voxel * box[3 + a];
    }
    creases_ = std::make_unique<MeshCreases>(surface, options.feature_angle, *this, 0.5 * voxel);
}

MeshSdf::~MeshSdf() = default;

double sdf_memory_estimate(const TriangleSurface& surface, double voxel, double exterior_band,
                           double interior_band) {
    const double voxels =
        surface_area(surface) / (voxel * voxel) * (exterior_band + interior_band + 1);
    return 2 * 16 * voxels;
}

Box3 MeshSdf::bounds() const {
    // The interpolated zero level of a face lying on the box may sit a few 1e-5 voxel outside
    // it (single-precision distances): a margin keeps u > 0 just beyond the returned box.
    const Vec3 margin = Vec3::Constant(1e-2 * grid_->voxel);
    return {bounds_.lo - margin, bounds_.hi + margin};
}
double MeshSdf::voxel_size() const {
    return grid_->voxel;
}
long long MeshSdf::active_voxels() const {
    return grid_->grid->active_voxels();
}
size_t MeshSdf::memory_bytes() const {
    return grid_->grid->memory_bytes();
}
bool MeshSdf::signed_by_winding_number() const {
    return grid_->by_winding;
}

double MeshSdf::value(const Vec3& p) const {
    const Grid& g = *grid_;
    if (!(p.array() >= g.band_box.lo.array()).all() || !(p.array() <= g.band_box.hi.array()).all())
        return std::max(g.exterior, distance_to_box(bounds_, p));
    const Vec3 q = (p - g.origin) / g.voxel;
    const Vec3 base = q.array().floor();
    const Vec3 t = q - base;
    double f[8];
    g.grid->corner_values(int(base.x()), int(base.y()), int(base.z()), f);
    double v = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
        const double w =
            (i ? t.x() : 1 - t.x()) * (j ? t.y() : 1 - t.y()) * (k ? t.z() : 1 - t.z());
        v += w * f[corner];
    }
    return v;
}

Vec3 MeshSdf::gradient(const Vec3& p) const {
    const Grid& g = *grid_;
    const Vec3 outward = p - bounds_.center();
    const Vec3 fallback = outward.norm() > 0 ? Vec3(outward.normalized()) : Vec3(Vec3::UnitZ());
    if (!(p.array() >= g.band_box.lo.array()).all() ||
        !(p.array() <= g.band_box.hi.array()).all()) {
        const Vec3 away = p - p.cwiseMax(bounds_.lo).cwiseMin(bounds_.hi);
        return away.norm() > g.exterior ? Vec3(away.normalized()) : fallback;
    }
    const Vec3 q = (p - g.origin) / g.voxel;
    const Vec3 base = q.array().floor();
    const Vec3 t = q - base;
    double values[8];
    g.grid->corner_values(int(base.x()), int(base.y()), int(base.z()), values);
    Vec3 grad = Vec3::Zero();
    for (int corner = 0; corner < 8; ++corner) {
        const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
        const Vec3 w(i ? t.x() : 1 - t.x(), j ? t.y() : 1 - t.y(), k ? t.z() : 1 - t.z());
        const Vec3 dw(i ? 1 : -1, j ? 1 : -1, k ? 1 : -1);
        const double f = values[corner];
        grad += f * Vec3(dw.x() * w.y() * w.z(), w.x() * dw.y() * w.z(), w.x() * w.y() * dw.z());
    }
    grad /= g.voxel;
    // Off the band the eight values are all the same clamped constant: no direction there.
    return grad.norm() > 1e-3 ? grad : fallback;
}

void MeshSdf::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const double u = value(p);
    if (!creases_->add_pieces(p, tolerance, u, 0.5 * grid_->voxel, out))
        out.push_back({u, gradient(p)});
}

void MeshSdf::write_vdb(const std::string& path) const {
    grid_->grid->write_vdb(path);
}

}  // namespace hexmesh

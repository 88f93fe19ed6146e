#include "surface/mesh_sdf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>
#include <stdexcept>
#include <unordered_map>

#include "surface/winding_number.h"

namespace hexmesh {
namespace {

// Hands the triangles to OpenVDB in index space, computed in double precision relative to
// the grid origin (world = origin + voxel * index), so large coordinates keep their digits.
struct IndexSpaceMesh {
    const TriangleSurface& surface;
    Vec3 origin;
    double inverse_voxel;

    size_t polygonCount() const { return surface.triangles.size(); }
    size_t pointCount() const { return surface.points.size(); }
    size_t vertexCount(size_t) const { return 3; }
    void getIndexSpacePoint(size_t n, size_t v, openvdb::Vec3d& pos) const {
        const Vec3 q = (surface.points[surface.triangles[n][v]] - origin) * inverse_voxel;
        pos = openvdb::Vec3d(q.x(), q.y(), q.z());
    }
};

// Distance from p to the box (0 inside it).
double distance_to_box(const Box3& box, const Vec3& p) {
    return (box.lo - p).cwiseMax(p - box.hi).cwiseMax(0.0).norm();
}

bool has_boundary_edges(const TriangleSurface& s) {
    std::unordered_map<std::uint64_t, int> uses;
    uses.reserve(2 * s.triangles.size());
    for (const auto& t : s.triangles)
        for (int e = 0; e < 3; ++e) {
            const int a = t[e], b = t[(e + 1) % 3];
            ++uses[edge_key(a, b)];
        }
    for (const auto& [edge, n] : uses)
        if (n == 1) return true;
    return false;
}

// Unsigned distances in the band, then each active voxel signed by the winding number
// at its centre, then the inactive tiles by a signed flood fill of those signs.
openvdb::FloatGrid::Ptr winding_signed_grid(const TriangleSurface& surface,
                                            const IndexSpaceMesh& mesh,
                                            const openvdb::math::Transform& transform,
                                            const MeshSdfOptions& o, double voxel) {
    const float band = float(std::max(o.exterior_band, o.interior_band));
    auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        mesh, transform, band, band, openvdb::tools::UNSIGNED_DISTANCE_FIELD);
    const WindingNumber winding(surface);
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(grid->tree());
    // Face neighbours a and b (one voxel apart) cannot lie on two sides of the surface when
    // udf(a) + udf(b) > voxel: then b copies a's sign instead of a winding-number query.
    // Voxels are visited in offset order, so the -x, -y, -z neighbours in the leaf are done.
    const float step = float(voxel);
    leaves.foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
        using Leaf = openvdb::FloatTree::LeafNodeType;
        for (openvdb::Index offset = 0; offset < Leaf::SIZE; ++offset) {
            if (!leaf.isValueOn(offset)) continue;
            const float udf = leaf.getValue(offset);
            const openvdb::Coord local = Leaf::offsetToLocalCoord(offset);
            int sign = 0;
            for (int a = 0; a < 3 && sign == 0; ++a) {
                if (local[a] == 0) continue;
                const openvdb::Index n = offset - (a == 0 ? Leaf::DIM * Leaf::DIM : a == 1 ? Leaf::DIM : 1);
                if (leaf.isValueOn(n) && std::abs(leaf.getValue(n)) + udf > step)
                    sign = leaf.getValue(n) < 0 ? -1 : 1;
            }
            if (sign == 0) {
                const openvdb::Coord c = leaf.offsetToGlobalCoord(offset);
                sign = winding(mesh.origin + voxel * Vec3(c.x(), c.y(), c.z())) > 0.5 ? -1 : 1;
            }
            if (sign < 0) leaf.setValueOnly(offset, -udf);
        }
    });
    openvdb::tools::signedFloodFillWithValues(grid->tree(), float(o.exterior_band * voxel),
                                              float(-o.interior_band * voxel));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    return grid;
}

}  // namespace

struct MeshSdf::Grid {
    openvdb::FloatGrid::Ptr grid;
    Vec3 origin;
    double voxel = 0;
    double exterior = 0;  // band half-widths, geometry units
    double interior = 0;
    Box3 band_box;        // world box of the active voxels
    bool by_winding = false;
};

MeshSdf::MeshSdf(const TriangleSurface& surface, const MeshSdfOptions& options)
    : grid_(std::make_unique<Grid>()) {
    if (surface.triangles.empty()) throw std::invalid_argument("MeshSdf: empty surface");
    if (!(options.feature_angle >= 0 && options.feature_angle <= 180))
        throw std::invalid_argument("MeshSdf: feature angle must lie in [0, 180] degrees");
    if (!(options.exterior_band >= 1 && options.interior_band >= 1))
        throw std::invalid_argument("MeshSdf: band half-widths must be at least 1 voxel");
    static std::once_flag init;
    std::call_once(init, [] { openvdb::initialize(); });

    bounds_ = surface_bounds(surface);
    const double extent = bounds_.size().maxCoeff();
    double voxel = options.voxel_size;
    if (voxel <= 0) {
        if (options.resolution < 2) throw std::invalid_argument("MeshSdf: resolution must be >= 2");
        voxel = extent / options.resolution;
    }
    if (!(voxel > 0) || !std::isfinite(voxel) || extent / voxel > 1e5)
        throw std::invalid_argument("MeshSdf: voxel size must be positive and at least 1e-5 of "
                                    "the surface's extent");

    Grid& g = *grid_;
    g.voxel = voxel;
    g.origin = bounds_.lo;
    g.exterior = options.exterior_band * voxel;
    g.interior = options.interior_band * voxel;
    auto transform = openvdb::math::Transform::createLinearTransform(voxel);
    transform->postTranslate(openvdb::Vec3d(g.origin.x(), g.origin.y(), g.origin.z()));
    const IndexSpaceMesh mesh{surface, g.origin, 1.0 / voxel};
    g.by_winding = options.sign == SdfSign::winding_number ||
                   (options.sign == SdfSign::automatic && has_boundary_edges(surface));
    if (g.by_winding)
        g.grid = winding_signed_grid(surface, mesh, *transform, options, voxel);
    else
        g.grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
            mesh, *transform, float(options.exterior_band), float(options.interior_band));
    g.grid->setName("sdf");

    const openvdb::CoordBBox box = g.grid->evalActiveVoxelBoundingBox();
    if (box.empty()) throw std::invalid_argument("MeshSdf: the conversion produced no voxel");
    for (int a = 0; a < 3; ++a) {
        g.band_box.lo[a] = g.origin[a] + voxel * box.min()[a];
        g.band_box.hi[a] = g.origin[a] + voxel * box.max()[a];
    }
    creases_ = std::make_unique<MeshCreases>(surface, options.feature_angle, *this, 0.5 * voxel);
}

MeshSdf::~MeshSdf() = default;

Box3 MeshSdf::bounds() const {
    // The interpolated zero level of a face lying on the box may sit a few 1e-5 voxel outside
    // it (single-precision distances): a margin keeps u > 0 just beyond the returned box.
    const Vec3 margin = Vec3::Constant(1e-2 * grid_->voxel);
    return {bounds_.lo - margin, bounds_.hi + margin};
}
double MeshSdf::voxel_size() const { return grid_->voxel; }
long long MeshSdf::active_voxels() const { return (long long)grid_->grid->activeVoxelCount(); }
size_t MeshSdf::memory_bytes() const { return grid_->grid->memUsage(); }
bool MeshSdf::signed_by_winding_number() const { return grid_->by_winding; }

double MeshSdf::value(const Vec3& p) const {
    const Grid& g = *grid_;
    if (!(p.array() >= g.band_box.lo.array()).all() || !(p.array() <= g.band_box.hi.array()).all())
        return std::max(g.exterior, distance_to_box(bounds_, p));
    const Vec3 q = (p - g.origin) / g.voxel;
    const Vec3 base = q.array().floor();
    const Vec3 t = q - base;
    const openvdb::Coord c0(int(base.x()), int(base.y()), int(base.z()));
    openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(g.grid->tree());
    double v = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
        const double w = (i ? t.x() : 1 - t.x()) * (j ? t.y() : 1 - t.y()) * (k ? t.z() : 1 - t.z());
        v += w * acc.getValue(c0.offsetBy(i, j, k));
    }
    return v;
}

Vec3 MeshSdf::gradient(const Vec3& p) const {
    const Grid& g = *grid_;
    const Vec3 outward = p - bounds_.center();
    const Vec3 fallback = outward.norm() > 0 ? Vec3(outward.normalized()) : Vec3(Vec3::UnitZ());
    if (!(p.array() >= g.band_box.lo.array()).all() || !(p.array() <= g.band_box.hi.array()).all()) {
        const Vec3 away = p - p.cwiseMax(bounds_.lo).cwiseMin(bounds_.hi);
        return away.norm() > g.exterior ? Vec3(away.normalized()) : fallback;
    }
    const Vec3 q = (p - g.origin) / g.voxel;
    const Vec3 base = q.array().floor();
    const Vec3 t = q - base;
    const openvdb::Coord c0(int(base.x()), int(base.y()), int(base.z()));
    openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(g.grid->tree());
    Vec3 grad = Vec3::Zero();
    for (int corner = 0; corner < 8; ++corner) {
        const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
        const Vec3 w(i ? t.x() : 1 - t.x(), j ? t.y() : 1 - t.y(), k ? t.z() : 1 - t.z());
        const Vec3 dw(i ? 1 : -1, j ? 1 : -1, k ? 1 : -1);
        const double f = acc.getValue(c0.offsetBy(i, j, k));
        grad += f * Vec3(dw.x() * w.y() * w.z(), w.x() * dw.y() * w.z(), w.x() * w.y() * dw.z());
    }
    grad /= g.voxel;
    // Off the band the eight values are all the same clamped constant: no direction there.
    return grad.norm() > 1e-3 ? grad : fallback;
}

void MeshSdf::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const double u = value(p);
    if (!creases_->add_pieces(p, tolerance, u, 0.5 * grid_->voxel, out)) out.push_back({u, gradient(p)});
}

void MeshSdf::write_vdb(const std::string& path) const {
    openvdb::io::File file(path);
    file.write({grid_->grid});
    file.close();
}

}  // namespace hexmesh

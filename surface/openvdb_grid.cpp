// The OpenVDB module of MeshSdf (surface/sdf_grid.h): built as its own shared object,
// loaded on first use.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "surface/sdf_grid.h"

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

// world = origin + voxel * index.
openvdb::math::Transform::Ptr world_transform(double voxel, const Vec3& origin) {
    auto transform = openvdb::math::Transform::createLinearTransform(voxel);
    transform->postTranslate(openvdb::Vec3d(origin.x(), origin.y(), origin.z()));
    return transform;
}

// Unsigned distances in the band, then each active voxel signed by the winding number
// (o.winding) at its centre, then the inactive tiles by a signed flood fill of those signs.
// `voxel` is the grid's own (transform's) voxel, the unit of its distances.
openvdb::FloatGrid::Ptr winding_signed_grid(const IndexSpaceMesh& mesh,
                                            const openvdb::math::Transform& transform,
                                            const SdfGridSpec& o, double voxel) {
    const float band = float(std::max(o.exterior_band, o.interior_band));
    auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        mesh, transform, band, band, openvdb::tools::UNSIGNED_DISTANCE_FIELD);
    const std::function<double(const Vec3&)>& winding = o.winding;
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(grid->tree());
    // Face neighbours a and b (one voxel apart) cannot lie on two sides of the surface when
    // udf(a) + udf(b) > voxel: then b copies a's sign instead of a winding-number query.
    // Voxels are visited in offset order, so the -x, -y, -z neighbours in the leaf are done.
    const float step = float(voxel);
    leaves.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
        using Leaf = openvdb::FloatTree::LeafNodeType;
        for (openvdb::Index offset = 0; offset < Leaf::SIZE; ++offset) {
            if (!leaf.isValueOn(offset)) continue;
            const float udf = leaf.getValue(offset);
            const openvdb::Coord local = Leaf::offsetToLocalCoord(offset);
            int sign = 0;
            for (int a = 0; a < 3 && sign == 0; ++a) {
                if (local[a] == 0) continue;
                constexpr openvdb::Index stride[3] = {Leaf::DIM * Leaf::DIM, Leaf::DIM, 1};
                const openvdb::Index n = offset - stride[a];
                if (leaf.isValueOn(n) && std::abs(leaf.getValue(n)) + udf > step)
                    sign = leaf.getValue(n) < 0 ? -1 : 1;
            }
            if (sign == 0) {
                const openvdb::Coord c = leaf.offsetToGlobalCoord(offset);
                sign = winding(mesh.origin + o.voxel * Vec3(c.x(), c.y(), c.z())) > 0.5 ? -1 : 1;
            }
            if (sign < 0) leaf.setValueOnly(offset, -udf);
        }
    });
    openvdb::tools::signedFloodFillWithValues(grid->tree(), float(o.exterior_band * voxel),
                                              float(-o.interior_band * voxel));
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    return grid;
}

// The voxel OpenVDB builds a grid with: the true one, or for a voxel so small that OpenVDB
// refuses its transform (under about 1e-5: the determinant of its scale is compared to zero;
// a body of a few millimetres given in metres), the true one scaled by a power of two into
// [1, 2). Scaled back (exactly: by a power of two), its distances are the true ones, but for
// OpenVDB's absolute tolerances, which are then relative to the voxel as they should be.
struct ScaledVoxel {
    double voxel;      // the voxel OpenVDB works with: the true one times 2^exponent
    int exponent = 0;  // 0: the true voxel
};

ScaledVoxel scaled_voxel(double voxel) {
    int e = 0;
    std::frexp(voxel, &e);  // voxel = m 2^e, m in [0.5, 1)
    return {std::ldexp(voxel, 1 - e), 1 - e};
}

class OpenVdbGrid : public SdfGrid {
  public:
    OpenVdbGrid(openvdb::FloatGrid::Ptr grid, const SdfGridSpec& spec, int exponent)
        : grid_(std::move(grid)), voxel_(spec.voxel), exponent_(exponent) {}

    void corner_values(int i, int j, int k, double (&values)[8]) const override {
        openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(grid_->tree());
        const openvdb::Coord c0(i, j, k);
        for (int corner = 0; corner < 8; ++corner)
            values[corner] = std::ldexp(
                double(acc.getValue(c0.offsetBy(corner & 1, (corner >> 1) & 1, corner >> 2))),
                -exponent_);
    }
    std::array<int, 6> active_box() const override {
        const openvdb::CoordBBox box = grid_->evalActiveVoxelBoundingBox();
        if (box.empty()) return {1, 1, 1, 0, 0, 0};
        return {box.min().x(), box.min().y(), box.min().z(),
                box.max().x(), box.max().y(), box.max().z()};
    }
    long long active_voxels() const override { return (long long)grid_->activeVoxelCount(); }
    size_t memory_bytes() const override { return grid_->memUsage(); }
    // A scaled grid cannot be written: OpenVDB refused its true voxel's transform.
    void write_vdb(const std::string& path) const override {
        if (exponent_ != 0) {
            std::ostringstream message;
            message << "OpenVDB cannot write a grid of voxel " << voxel_
                    << " (its smallest is about 1e-5): give the surface in smaller units (e.g. "
                       "millimetres instead of metres)";
            throw std::runtime_error(message.str());
        }
        openvdb::io::File file(path);
        file.write({grid_});
        file.close();
    }

  private:
    openvdb::FloatGrid::Ptr grid_;
    double voxel_;
    int exponent_;
};

}  // namespace
}  // namespace hexmesh

extern "C" hexmesh::SdfGrid* hexmesh_build_sdf_grid(const hexmesh::TriangleSurface& surface,
                                                    const hexmesh::SdfGridSpec& spec) {
    using namespace hexmesh;
    static std::once_flag init;
    std::call_once(init, [] { openvdb::initialize(); });
    ScaledVoxel scaled{spec.voxel};
    openvdb::math::Transform::Ptr transform;
    try {
        transform = world_transform(spec.voxel, spec.origin);
    } catch (const openvdb::ArithmeticError&) {
        scaled = scaled_voxel(spec.voxel);
        transform = world_transform(scaled.voxel, std::ldexp(1.0, scaled.exponent) * spec.origin);
    }
    const IndexSpaceMesh mesh{surface, spec.origin, 1.0 / spec.voxel};
    openvdb::FloatGrid::Ptr grid =
        spec.winding ? winding_signed_grid(mesh, *transform, spec, scaled.voxel)
                     : openvdb::tools::meshToVolume<openvdb::FloatGrid>(
                           mesh, *transform, float(spec.exterior_band), float(spec.interior_band));
    grid->setName("sdf");
    return new OpenVdbGrid(std::move(grid), spec, scaled.exponent);
}

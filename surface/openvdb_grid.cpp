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

// Unsigned distances in the band, then each active voxel signed by the winding number
// (o.winding) at its centre, then the inactive tiles by a signed flood fill of those signs.
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

class OpenVdbGrid : public SdfGrid {
  public:
    explicit OpenVdbGrid(openvdb::FloatGrid::Ptr grid) : grid_(std::move(grid)) {}

    void corner_values(int i, int j, int k, double (&values)[8]) const override {
        openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(grid_->tree());
        const openvdb::Coord c0(i, j, k);
        for (int corner = 0; corner < 8; ++corner)
            values[corner] = acc.getValue(c0.offsetBy(corner & 1, (corner >> 1) & 1, corner >> 2));
    }
    std::array<int, 6> active_box() const override {
        const openvdb::CoordBBox box = grid_->evalActiveVoxelBoundingBox();
        if (box.empty()) return {1, 1, 1, 0, 0, 0};
        return {box.min().x(), box.min().y(), box.min().z(),
                box.max().x(), box.max().y(), box.max().z()};
    }
    long long active_voxels() const override { return (long long)grid_->activeVoxelCount(); }
    size_t memory_bytes() const override { return grid_->memUsage(); }
    void write_vdb(const std::string& path) const override {
        openvdb::io::File file(path);
        file.write({grid_});
        file.close();
    }

  private:
    openvdb::FloatGrid::Ptr grid_;
};

}  // namespace
}  // namespace hexmesh

extern "C" hexmesh::SdfGrid* hexmesh_build_sdf_grid(const hexmesh::TriangleSurface& surface,
                                                    const hexmesh::SdfGridSpec& spec) {
    using namespace hexmesh;
    static std::once_flag init;
    std::call_once(init, [] { openvdb::initialize(); });
    auto transform = openvdb::math::Transform::createLinearTransform(spec.voxel);
    transform->postTranslate(openvdb::Vec3d(spec.origin.x(), spec.origin.y(), spec.origin.z()));
    const IndexSpaceMesh mesh{surface, spec.origin, 1.0 / spec.voxel};
    openvdb::FloatGrid::Ptr grid =
        spec.winding ? winding_signed_grid(mesh, *transform, spec, spec.voxel)
                     : openvdb::tools::meshToVolume<openvdb::FloatGrid>(
                           mesh, *transform, float(spec.exterior_band), float(spec.interior_band));
    grid->setName("sdf");
    return new OpenVdbGrid(std::move(grid));
}

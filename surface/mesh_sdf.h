// Signed distance to a triangle surface, sampled on an OpenVDB narrow-band grid.
#pragma once

#include <memory>
#include <string>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "surface/mesh_creases.h"

namespace hexmesh {

// How inside and outside are told apart.
// - flood_fill: OpenVDB's exterior flood through the voxels; needs a closed surface (holes
//   up to about a voxel are sealed), any orientation.
// - winding_number: the fast generalized winding number at every band voxel (> 1/2:
//   inside); needs consistently oriented triangles, tolerates holes; slower.
// - automatic: winding_number when the surface has open (boundary) edges, else flood_fill.
enum class SdfSign { automatic, flood_fill, winding_number };

struct MeshSdfOptions {
    // Voxel edge in geometry units; 0: the longest side of the surface's box / resolution.
    double voxel_size = 0;
    int resolution = 256;
    // Half-widths of the band of exact distances, in voxels, outside and inside.
    double exterior_band = 3;
    double interior_band = 3;
    SdfSign sign = SdfSign::automatic;
    // Edges whose two triangles turn by more than this (degrees) are sharp creases, exposed
    // through active_pieces() (surface/mesh_creases.h); 180: none, the body is smooth.
    double feature_angle = 30;
    // Refuse a field whose voxels would take more memory than this (bytes; 0: memory_limit(),
    // hexmesh/core/memory_limit.h), estimated from the surface's area before anything is
    // allocated.
    double max_bytes = 0;
};

// The memory a band of exact distances around `surface` takes at this voxel size and these
// band half-widths (voxels), from its area: the band's voxels at about 16 bytes each (OpenVDB
// float leaves and their masks), doubled for the conversion's own index grid.
double sdf_memory_estimate(const TriangleSurface& surface, double voxel, double exterior_band,
                           double interior_band);

// u(x): the distance to the surface, negative inside, computed by OpenVDB's mesh-to-volume
// conversion in a band around the surface and interpolated trilinearly from the voxel
// centres (value and its exact piecewise gradient); the sign as MeshSdfOptions::sign says.
//
// Away from the band value() never overstates the distance, so sphere tracing and the
// projection V stay safe: outside the band it is +-(band width), and outside the box of
// the band the distance to the surface's bounding box when larger; the gradient there is
// the direction from the box centre (outward), so projection steps walk towards the band.
// Near the surface's sharp creases and corners active_pieces() gives the planes of the
// triangles meeting there (surface/mesh_creases.h), elsewhere the one smooth piece.
// Thread safe for concurrent value()/gradient()/active_pieces() calls.
class MeshSdf : public ImplicitFunction {
  public:
    // Throws std::invalid_argument for an empty surface or bad options.
    explicit MeshSdf(const TriangleSurface& surface, const MeshSdfOptions& options = {});
    ~MeshSdf() override;
    MeshSdf(const MeshSdf&) = delete;
    MeshSdf& operator=(const MeshSdf&) = delete;

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    Box3 bounds() const override;  // the surface's bounding box, 0.01 voxel wider

    double voxel_size() const;
    long long active_voxels() const;
    size_t memory_bytes() const;  // of the OpenVDB tree
    bool signed_by_winding_number() const;
    const MeshCreases& creases() const { return *creases_; }

    // Writes the grid (named "sdf", a level set) to an OpenVDB .vdb file.
    void write_vdb(const std::string& path) const;

  private:
    struct Grid;
    std::unique_ptr<Grid> grid_;
    std::unique_ptr<MeshCreases> creases_;
    Box3 bounds_;
};

}  // namespace hexmesh

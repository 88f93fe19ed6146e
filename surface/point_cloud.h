// Implicit body from an oriented point cloud: a smoothed signed distance to the points' planes.
#pragma once

#include <memory>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/point_samples.h"

namespace hexmesh {

struct PointCloudSdfOptions {
    int neighbours = 12;   // k: points blended at each query, 1..64
    double bandwidth = 0;  // h of the Gaussian weights, geometry units; 0: the mean spacing
};

// u(x) = sum_i w_i n_i.(x - p_i) / sum_i w_i over the k points p_i nearest to x, n_i the
// unit normals (normalized here; they must point out of the body, so u < 0 inside), with
//   w_i = exp(-|x - p_i|^2 / h^2) (1 - |x - p_i|^2 / R^2)^2,
// R the distance to the (k+1)-th nearest point: the taper makes u continuous where the set
// of nearest points changes. h defaults to the mean distance from a point to its nearest
// neighbour (the spacing). Near a smooth, well-sampled surface u is the signed distance to
// within about spacing^2 / curvature radius; far away it tends to the distance to the
// nearest point's tangent plane, which has the right sign. gradient() is the exact
// gradient of u, which has small kinks where the (k+1)-th neighbour changes. Nearest
// neighbours come from a CGAL k-d tree built in the constructor; value() and gradient()
// are safe to call concurrently.
class PointCloudSdf : public ImplicitFunction {
  public:
    // Throws std::invalid_argument for no point, points and normals of different counts,
    // a zero or non-finite normal or point, or bad options.
    explicit PointCloudSdf(const OrientedPoints& cloud, const PointCloudSdfOptions& options = {});
    ~PointCloudSdf() override;
    PointCloudSdf(const PointCloudSdf&) = delete;
    PointCloudSdf& operator=(const PointCloudSdf&) = delete;

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    // The points' box enlarged by 3 h and 1% of its diagonal on every side.
    Box3 bounds() const override;

    double bandwidth() const { return bandwidth_; }
    double mean_spacing() const { return mean_spacing_; }

  private:
    double evaluate(const Vec3& p, Vec3* gradient) const;

    struct Tree;
    std::unique_ptr<Tree> tree_;
    std::vector<Vec3> normals_;
    int neighbours_ = 12;
    double bandwidth_ = 0, mean_spacing_ = 0;
    Box3 bounds_;
};

// Health report of an oriented point cloud, for `hexmesh inspect`.
struct PointCloudDiagnostics {
    long long points = 0;
    Box3 bounds;
    double mean_spacing = 0;   // mean distance from a point to its nearest other point
    double largest_gap = 0;    // the largest such distance (an undersampled region)
    long long duplicates = 0;  // points with another at the same place (1e-12 of the box)
    // Points whose normal points against the summed normals of their `neighbours` nearest
    // points: flipped normals, or sheets closer than the spacing (thin walls).
    long long inconsistent_normals = 0;
};

// Throws std::invalid_argument for points and normals of different counts or neighbours
// outside 1..64.
PointCloudDiagnostics diagnose_point_cloud(const OrientedPoints& cloud, int neighbours = 12);

}  // namespace hexmesh

// Sharp features of a triangle surface: crease polylines by dihedral angle, corners where
// creases meet, and projection of a point onto the nearest crease.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "hexmesh/core/triangle_surface.h"

namespace hexmesh {

struct FeatureOptions {
    // An edge shared by two triangles is a crease when their normals differ by more than
    // this angle (degrees; 0 <= angle < 180). A flat edge turns by 0, a box edge by 90.
    double angle_degrees = 30;
    // Edges of one triangle (holes, the rim of an open sheet) and of three or more
    // (non-manifold) are features too.
    bool include_boundary = true;
    // A faceted scan has no gap between its creases and its facets: on an animal of 6 000
    // points 38 % of all edges turn by more than 30 degrees and 27 % by 15-30, around the
    // former as much as anywhere; a CAD part's edges beside its creases turn by a few degrees
    // (a flat face) or by its creases' angle. When the edges that turn by between half the
    // angle and the angle and touch a crease number at least this share of the creases' edges,
    // no edge is a crease (FeatureCurves::noise). On the shared surfaces that share is 0-0.37
    // for the CAD parts and 0.71-1.53 for the scans. 0: never.
    double noise_ratio = 0;
};

// The noise_ratio `tetmesh` takes (and `inspect` reports by): 0.5, between the CAD surfaces'
// 0.37 at most and the scans' 0.71 at least.
inline constexpr double facet_noise_ratio = 0.5;

struct FeatureCurves {
    // Point ids along each crease polyline, at least 2. Open chains run from corner to
    // corner; a closed loop without corner repeats its first id at the end.
    std::vector<std::vector<int>> chains;
    // Point ids where 1 or at least 3 feature edges meet (the box's 8 corners); a corner
    // projects onto itself and the optimizer fixes it.
    std::vector<int> corners;
    // Edges of two triangles turning by more than the angle, and by between half of it and it
    // with an end on one of the former; noise: the creases were dropped by
    // FeatureOptions::noise_ratio.
    int turning_edges = 0, half_turning_edges = 0;
    bool noise = false;
    // Whether the surface is a faceted scan by FeatureOptions::noise_ratio `ratio` (> 0).
    bool scan_at(double ratio) const {
        return turning_edges > 0 && half_turning_edges >= ratio * double(turning_edges);
    }
};

// Normals follow the triangles' orientation; a pair of triangles running their common
// edge the same way (inconsistent orientation) is compared with one normal flipped.
// Zero-area triangles are ignored.
FeatureCurves detect_sharp_features(const TriangleSurface& surface,
                                    const FeatureOptions& options = {});

struct FeatureProjection {
    Vec3 point;        // the closest point on any chain
    int chain = -1;    // index into FeatureCurves::chains (-1: there is no chain)
    int segment = -1;  // the segment chain[segment] -> chain[segment + 1]
    double distance = 0;
};

// Nearest point of the crease polylines to p (brute force: O(#feature edges) per call).
FeatureProjection project_to_features(const TriangleSurface& surface, const FeatureCurves& features,
                                      const Vec3& p);

// The crease polylines indexed for nearest-point queries (a CGAL AABB tree of their
// segments): project_to_features's answer in logarithmic time, for the optimizer's many
// projections. Where two segments are equally near (a chain's joint) either may be named.
// Copies what it needs; queries are const and may run in parallel.
class FeatureIndex {
  public:
    FeatureIndex(const TriangleSurface& surface, const FeatureCurves& features);
    ~FeatureIndex();
    FeatureIndex(const FeatureIndex&) = delete;
    FeatureIndex& operator=(const FeatureIndex&) = delete;

    bool empty() const { return segments_.empty(); }
    FeatureProjection project(const Vec3& p) const;  // chain -1 when empty()

  private:
    struct Tree;
    std::vector<std::pair<int, int>> segments_;  // (chain, segment) of each indexed segment
    std::unique_ptr<Tree> tree_;
};

}  // namespace hexmesh

// A one-to-one map of a closed genus-0 triangle surface onto the unit sphere, and back.
#pragma once

#include <functional>
#include <memory>
#include <ostream>

#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "surface/exact_distance.h"
#include "untangle/untangle.h"

namespace hexmesh {

struct SphereMapOptions {
    // Volume (area) weight of the functional the map minimizes: 0 keeps the triangles' shapes
    // (conformal), 1 their areas (a leg keeps its share of the sphere). The wall lattice taken
    // through the map folds less the more conformal the map: quads folded on the surface at 20
    // cells per edge, theta 0.95 / 0.8 / 0.5 / 0.3 / 0.1: bull 280 / 177 / 106 / 77 / 53,
    // camel - / - / 138 / 107 / 69, spool - / - / 81 / 67 / 51 (bench/RESULTS.md). Sizing the
    // targets by curvature instead (smaller cells round legs) made it fold 2-4 times more.
    // At 0.3 instead of 0.5, 3 more of the 20 runs on the shared bodies give a valid grid.
    double theta = 0.3;
    int iterations = 60;  // barrier outer iterations
    // The surface is simplified or refined first to about this many triangles: the map need
    // only place the wall grid's nodes, which are then projected onto the body.
    int triangles = 3000;
    untangle::SolverOptions solver = untangle::loose_solve();
    std::ostream* log = nullptr;  // the optimization's summary
};

// The map: the surface's points (welded, holes capped) and their images on the unit sphere,
// every triangle counter-clockwise seen from outside on both.
class SphereMap {
  public:
    SphereMap(TriangleSurface surface, std::vector<Vec3> sphere);
    ~SphereMap();
    SphereMap(SphereMap&&) noexcept;

    // The surface point whose image is the unit vector q: barycentric in the spherical triangle
    // (its flat chord triangle, seen from the centre) that holds q.
    Vec3 surface_point(const Vec3& q) const;

    const TriangleSurface& surface() const { return surface_; }
    const std::vector<Vec3>& sphere() const { return sphere_; }
    Id inverted() const;  // triangles turning clockwise on the sphere (0 for a one-to-one map)

  private:
    struct Locator;
    TriangleSurface surface_;
    std::vector<Vec3> sphere_;
    std::unique_ptr<Locator> locator_;
};

// Maps a closed genus-0 surface (one piece; holes are capped by a fan first; simplified or
// refined to about `triangles` triangles) onto the sphere:
// Tutte's embedding of the surface without one point (the highest) in a disk, bounded by that
// point's neighbours on a circle (one to one: every point the mean of its neighbours), carried
// onto the sphere by the inverse stereographic projection with the removed point at the north
// pole; then the 2D functional (docs/architecture.md#the-functional) on the sphere (points
// sliding on it), each triangle's target its own shape scaled so the targets cover the sphere,
// minimized with the barrier, which never lets a triangle turn over. When the map starts
// with triangles turned over that the functional leaves so (seen on a body with bent limbs,
// whose far parts Tutte's map squeezes into tiny triangles), it is made again with the removed
// point at the body's lowest point, then at its extremes along x and y, and the one with the fewest
// turned over kept (then the lowest energy); options.log says so. Throws
// std::invalid_argument for a surface that is not one closed piece of genus 0 once capped.
// With `start`, the first map is start(point) (unit vectors; some triangles may turn over,
// which the functional's untangling repairs) instead of Tutte's.
SphereMap map_to_sphere(const TriangleSurface& surface, const SphereMapOptions& options = {},
                        const std::function<Vec3(const Vec3&)>& start = {});

// The same map turned on the sphere (a rotation: shapes and areas kept) so that each surface
// point's image points, as nearly as a rotation allows, the way the point lies from `centre`
// (the rotation maximizing the area-weighted sum of image . direction, by the SVD of their
// correlation). The map's own turn is arbitrary (Tutte's disk starts anywhere on its ring), and
// the lattice's patches, numbered as the cube's, then face the sides of the body they are named
// after, so that lines from an interior core box run to the side facing it.
SphereMap aligned_with_body(const SphereMap& map, const Vec3& centre);

// The image under the map of the surface point nearest x (barycentric in the triangle holding
// it; `nearest` built on map.surface()), made unit: the map spread off the surface, for points
// on or near it.
Vec3 image_of_nearest(const SphereMap& map, const ExactDistance& nearest, const Vec3& x);

// The cube-sphere wall lattice (CubeSurfaceLattice numbering, volume/cube_sphere.h) with n
// cells per patch edge on the body: the equiangular cube-sphere directions of the unit cube,
// taken through the map to the surface, then projected onto u = 0 of `body`. Throws
// std::runtime_error when a node comes out not finite.
std::vector<Vec3> wall_from_sphere_map(const SphereMap& map, int cells_per_edge,
                                       const ImplicitFunction& body);

}  // namespace hexmesh

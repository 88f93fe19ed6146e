// Boundary-layer metrics of a block grid (first-layer thickness, growth ratio, wall
// orthogonality) and its Hausdorff distance to a triangle surface.
#pragma once

#include <array>
#include <string>

#include "hexmesh/core/block_grid.h"
#include "hexmesh/core/implicit_function.h"
#include "hexmesh/core/triangle_surface.h"
#include "hexmesh/quality/wall_quality.h"
#include "volume/stretching.h"

namespace hexmesh {

// Wall-normal lines: for every block face whose face_patch is "wall", every node x0 of the
// face and the nodes x1, x2, ... going into the block along the face's index direction
// (face kmax: k = nk-1, nk-2, ...; face imin: i = 0, 1, ...). A node shared by several
// blocks starts one line per block face. The wall normal at x0 is grad u / |grad u|,
// oriented into the grid: towards u < 0 when most nodes in the middle of the face's lines
// have u < 0 (interior grid), towards u > 0 otherwise (exterior grid); where grad u
// vanishes, the first edge direction stands in for it. A wall cell's first-layer thickness
// takes, at a crease or corner node, the normal of the piece its wall face lies on instead
// (see WallQuality). The law gives the targets
// (law.first_height, law.growth_ratio) and how many edges of a line form the boundary
// layer; law.layers == 0 means no law: targets 0 and growth ratios over whole lines.
// The hausdorff fields are left empty. Deterministic, parallel over the lines of a face.
WallQuality measure_wall(const BlockGrid& grid, const ImplicitFunction& body,
                         const WallLayers& law);

// measure_wall block by block, for a grid made (or read) one block at a time: add() each
// block, in order, with the grid holding its points (the whole grid or one of its own), then
// result(). The same numbers as measure_wall of the whole grid.
class WallMeter {
  public:
    WallMeter(const ImplicitFunction& body, const WallLayers& law);
    // With skip_first[d], the block is a part of a block cut at its first nodes along d: the
    // lines there, which the part before it measures too, count for its cells' first-layer
    // thickness but not again in the line measures (angles, growth ratios).
    void add(const BlockGrid& grid, const Block& block, const std::array<bool, 3>& skip_first = {});
    WallQuality result() const;

    // What has been added, as bytes for another process; merge() adds another WallMeter's
    // pack() (the same body and law) to this one.
    std::string pack() const;
    void merge(const std::string& packed);

  private:
    const ImplicitFunction& body_;
    WallLayers law_;
    WallQuality w_;  // counts, extremes and targets so far
    double thickness_sum_ = 0, angle_sum_ = 0, ratio_sum_ = 0;
    Id thickness_within_ = 0, angles_ = 0, ratios_within_ = 0;
};

struct HausdorffDistance {
    double grid_to_surface = 0;  // max over the grid's wall nodes of the distance to surface
    double surface_to_grid = 0;  // max over surface samples of the distance to the wall faces
    double hausdorff = 0;        // the larger of the two
    // Every vertex of the surface's triangles: its distance to the wall over the size of the
    // wall quad nearest to it (the square root of the quad's area), max and 99th percentile.
    // Above 0.5 the grid misses part of the body: it bridges a groove or skips a finger.
    double surface_in_cells_max = 0;
    double surface_in_cells_p99 = 0;
    // The vertex of that max and its distance to the wall.
    Vec3 surface_in_cells_at = Vec3::Zero();
    double surface_in_cells_distance = 0;
};

// Exact distances (CGAL AABB tree) between the grid's wall and a triangle surface. The
// grid's wall is its "wall" block faces, each quad (a, b, c, d) split into triangles
// (a, b, c) and (a, c, d); the surface is sampled at the vertices its triangles use and at
// the triangles' centroids, so surface_to_grid may fall short of the exact one-sided
// distance by at most the largest distance from a point of a triangle to its nearest
// sample (the distance is 1-Lipschitz). Throws std::invalid_argument when the
// grid has no wall face or the surface no triangle of non-zero area.
HausdorffDistance hausdorff_to_surface(const BlockGrid& grid, const TriangleSurface& surface);

// The "wall" faces of one block as triangles (a, b, c), (a, c, d), appended to `wall` (a
// node shared with an earlier block appears again: distances do not mind): triangles 2 q and
// 2 q + 1 are wall quad q.
void append_wall_triangles(const BlockGrid& grid, const Block& block, TriangleSurface& wall);

// hausdorff_to_surface with the grid's wall already gathered by append_wall_triangles.
HausdorffDistance hausdorff_to_surface(const TriangleSurface& wall, const TriangleSurface& surface);

// Only the surface-to-wall distance in wall cells of hausdorff_to_surface (its
// surface_in_cells_* fields; the others 0): the vertices of `surface` against the grid's wall
// (all 0 for a surface without triangles). Throws std::invalid_argument when the grid has no
// wall face or no wall quad of non-zero area.
HausdorffDistance surface_to_wall_in_cells(const BlockGrid& grid, const TriangleSurface& surface);

}  // namespace hexmesh

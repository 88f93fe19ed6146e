// A wall grid carried in from a far surface: the path each wall node came along.
#pragma once

#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

// The cube-sphere wall lattice (CubeSurfaceLattice numbering, volume/cube_sphere.h) and the
// path of each of its nodes out to a far surface, star-shaped around `centre`: lines[s] is the
// polyline of surface point s from the wall (front) to the far surface (back), along which a
// potential rises from 0 on the wall to `far_level` (levels[s], one value per point,
// increasing), e.g. a gradient line (hexmesh/pipeline/exterior_paths.h makes them). The
// surfaces of equal level are nested: grid layers laid along them do not cross.
struct WallPaths {
    int cells_per_edge = 0;
    Vec3 centre = Vec3::Zero();
    double far_level = 1;
    std::vector<std::vector<Vec3>> lines;
    std::vector<std::vector<double>> levels;
    // Unit directions from the centre of the lines' far-field nodes (empty: towards each
    // line's end).
    std::vector<Vec3> far_directions;
    // How many lines follow a fibre of the directions' harmonic extension (the rest, the
    // potential's gradient: hexmesh/pipeline/exterior_paths.h).
    Id fibres = 0;

    const Vec3& wall(size_t s) const { return lines[s].front(); }
    const Vec3& outer(size_t s) const { return lines[s].back(); }
};

}  // namespace hexmesh

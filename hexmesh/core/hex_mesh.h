// Unstructured hexahedral mesh: points plus 8 node ids per cell (VTK_HEXAHEDRON order).
#pragma once

#include <array>
#include <cassert>
#include <cstdint>
#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

struct HexMesh {
    std::vector<Vec3> points;  // #points
    std::vector<Id> hexes;     // 8 * #cells node ids, VTK order (see reference_hex.h)

    Id num_cells() const { return static_cast<Id>(hexes.size() / 8); }
    Id num_points() const { return static_cast<Id>(points.size()); }

    Id node(Id cell, int corner) const {
        assert(cell >= 0 && cell < num_cells() && corner >= 0 && corner < 8);
        return hexes[8 * cell + corner];
    }
    std::array<Vec3, 8> corners(Id cell) const {
        std::array<Vec3, 8> p;
        for (int c = 0; c < 8; ++c) p[c] = points[node(cell, c)];
        return p;
    }
};

// Tetrahedral mesh: points plus 4 node ids per cell, positively oriented.
struct TetMesh {
    std::vector<Vec3> points;
    std::vector<Id> tets;  // 4 * #cells

    Id num_cells() const { return static_cast<Id>(tets.size() / 4); }
    Id node(Id cell, int corner) const {
        assert(cell >= 0 && cell < num_cells() && corner >= 0 && corner < 4);
        return tets[4 * cell + corner];
    }
};

// A volume mesh as read from a file: hexahedra and/or tetrahedra over one point array, plus
// the per-point "fixed" flags the file carried (empty when it had none).
struct VolumeMesh {
    std::vector<Vec3> points;
    std::vector<Id> hexes;  // 8 per cell, VTK order
    std::vector<Id> tets;   // 4 per cell, VTK order (positive det[p1-p0, p2-p0, p3-p0])
    std::vector<std::uint8_t> fixed;

    Id num_hexes() const { return static_cast<Id>(hexes.size() / 8); }
    Id num_tets() const { return static_cast<Id>(tets.size() / 4); }
};

}  // namespace hexmesh

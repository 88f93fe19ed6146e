#include <Eigen/Geometry>
#include <algorithm>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/quality/tet_quality.h"
#include "volume/tet_mesh.h"

namespace hexmesh {

Id remove_boundary_caps(PlacedTetMesh& placed, double max_degrees) {
    static constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    static constexpr int edge_ends[6][2] = {{0, 1}, {0, 2}, {0, 3},
                                            {1, 2}, {1, 3}, {2, 3}};  // dihedral_angles order
    TetMesh& mesh = placed.mesh;
    using Face = std::array<Id, 3>;
    auto face_key = [&](Id t, int f) {
        Face key = {mesh.node(t, faces[f][0]), mesh.node(t, faces[f][1]),
                    mesh.node(t, faces[f][2])};
        std::sort(key.begin(), key.end());
        return key;
    };
    std::unordered_map<Face, int, ArrayHash<Id, 3>> uses;
    for (Id t = 0; t < mesh.num_cells(); ++t)
        for (int f = 0; f < 4; ++f) ++uses[face_key(t, f)];

    std::vector<Id> kept;
    kept.reserve(mesh.tets.size());
    Id removed = 0;
    for (Id t = 0; t < mesh.num_cells(); ++t) {
        int on_boundary = 0, outer_faces = 0;
        std::array<Vec3, 4> p;
        for (int a = 0; a < 4; ++a) {
            on_boundary += placed.dimension[mesh.node(t, a)] < 3;
            p[a] = mesh.points[mesh.node(t, a)];
        }
        for (int f = 0; f < 4; ++f) outer_faces += uses[face_key(t, f)] == 1;
        const auto angles = dihedral_angles(p);
        const int smallest = int(std::min_element(angles.begin(), angles.end()) - angles.begin());
        // At an edge along a crease the small angle is the body's own: that tet stays.
        const bool crease_edge = placed.dimension[mesh.node(t, edge_ends[smallest][0])] <= 1 &&
                                 placed.dimension[mesh.node(t, edge_ends[smallest][1])] <= 1;
        const bool cap =
            on_boundary == 4 && outer_faces >= 2 && !crease_edge && angles[smallest] < max_degrees;
        if (cap) {
            ++removed;
            continue;
        }
        for (int a = 0; a < 4; ++a) kept.push_back(mesh.node(t, a));
    }
    mesh.tets = std::move(kept);

    std::vector<Id> renumber(mesh.points.size(), -1);
    PlacedTetMesh out;
    for (Id& v : mesh.tets) {
        if (renumber[v] < 0) {
            renumber[v] = Id(out.mesh.points.size());
            out.mesh.points.push_back(mesh.points[v]);
            out.dimension.push_back(placed.dimension[v]);
        }
        v = renumber[v];
    }
    out.mesh.tets = std::move(mesh.tets);
    placed = std::move(out);
    return removed;
}

}  // namespace hexmesh

// Local reconnection of a tet mesh: edge removals (3-2 flips and their generalization) and
// 2-3 flips that raise the smallest dihedral angle of the tets they replace, and points
// inserted in slivers of boundary points. Existing points do not move and the boundary faces
// stay as they are.
#pragma once

#include <vector>

#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

struct FlipResult {
    Id edge_removals = 0;  // m tets around an inner edge became 2m - 4 (m = 3: a 3-2 flip)
    Id flips_23 = 0;       // two tets on an inner face became three
};

// Visits the tets whose smallest dihedral angle is below `below_degrees`, worst first, and
// replaces a tet and its neighbours by another triangulation of their union when that raises
// the smallest dihedral angle among them: edge removal (the 3 to 7 tets around an inner edge
// of the tet become the best triangulation of their ring joined to the edge's two ends) and
// 2-3 (two tets sharing a face become three around a new edge). Repeats until a pass
// changes nothing or after `passes` passes. Every tet must be positively oriented (exact
// predicate): a mesh with an inverted or flat tet is left as it is (nothing flipped), since
// a region around it has no well-defined re-triangulation. Tets stay positively oriented.
FlipResult improve_by_flips(TetMesh& mesh, double below_degrees, int passes = 8);

// A point inserted in each tet below `below_degrees` whose four points are all on the
// boundary (on_boundary, per point): its points can only slide on the surface and its creases,
// which seldom opens it. The tet and its neighbours across faces (then one more ring, if
// that is not enough) are replaced by the cone of their union's boundary faces from the new
// point, placed by a compass search from the tet's centroid on the cone's smallest dihedral
// angle; only when every tet of the cone is positive (then it fills the union) and its
// smallest angle is above the union's. No point of the union may be left inside it. New points are
// appended to mesh.points (inside the body). Returns their count; a mesh with an inverted
// or flat tet is left as it is.
Id insert_in_slivers(TetMesh& mesh, double below_degrees, const std::vector<bool>& on_boundary);

}  // namespace hexmesh

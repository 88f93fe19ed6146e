// The reference hexahedron: VTK node order, corner tetrahedra and outward faces.
#pragma once

#include <array>

namespace hexmesh {

//          7 -------- 6
//         /|         /|        node  (x,y,z) on the unit cube
//        / |        / |        0 (0,0,0)   4 (0,0,1)
//       4 -------- 5  |        1 (1,0,0)   5 (1,0,1)
//       |  3 ------|- 2        2 (1,1,0)   6 (1,1,1)
//       | /        | /         3 (0,1,0)   7 (0,1,1)
//   z y |/         |/
//   |/  0 -------- 1
//   +-- x
//
// Corner tet c = (c, a, b, d): corner c and its three edge neighbours, ordered so that
// det[a-c, b-c, d-c] > 0 on the unit cube. A hex is admissible when all 8 are > 0.
// Columns a, b, d are the local x-, y-, z-like edge directions Verdict uses for the
// scaled Jacobian at that corner.
inline constexpr std::array<std::array<int, 4>, 8> hex_corner_tets = {{
    {0, 1, 3, 4},
    {1, 2, 0, 5},
    {2, 3, 1, 6},
    {3, 0, 2, 7},
    {4, 7, 5, 0},
    {5, 4, 6, 1},
    {6, 5, 7, 2},
    {7, 6, 4, 3},
}};

// Faces as 4 nodes ordered counter-clockwise seen from outside (right-hand normal points out).
// Order: x=0, x=1, y=0, y=1, z=0, z=1.
inline constexpr std::array<std::array<int, 4>, 6> hex_faces = {{
    {0, 4, 7, 3},
    {1, 2, 6, 5},
    {0, 1, 5, 4},
    {2, 3, 7, 6},
    {0, 3, 2, 1},
    {4, 5, 6, 7},
}};

// The 12 edges as node pairs: 4 along x, 4 along y, 4 along z.
inline constexpr std::array<std::array<int, 2>, 12> hex_edges = {{
    {0, 1},
    {3, 2},
    {4, 5},
    {7, 6},
    {0, 3},
    {1, 2},
    {4, 7},
    {5, 6},
    {0, 4},
    {1, 5},
    {2, 6},
    {3, 7},
}};

// Axis (0 = x, 1 = y, 2 = z) of the edge between two edge-neighbour nodes.
constexpr int hex_edge_axis(int a, int b) {
    constexpr int x[8] = {0, 1, 1, 0, 0, 1, 1, 0}, y[8] = {0, 0, 1, 1, 0, 0, 1, 1};
    return x[a] != x[b] ? 0 : y[a] != y[b] ? 1 : 2;
}

}  // namespace hexmesh

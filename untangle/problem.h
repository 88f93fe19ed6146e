// What the untangler optimizes: vertices, their constraints, and tetrahedral elements with targets.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "hexmesh/core/reference_hex.h"
#include "hexmesh/core/types.h"
#include "hexmesh/core/vertex_kind.h"
#include "untangle/tet_energy.h"
#include "untangle/triangle_energy.h"

namespace hexmesh::untangle {

// The target of corner tet c of a hex whose edges along its local x, y, z have the given
// lengths: the box corner with the tet's three edges in the tet's column order.
inline TetTarget hex_corner_target(int c, const Vec3& edges) {
    const auto& t = hex_corner_tets[c];
    return box_corner_target(
        Vec3(edges[hex_edge_axis(t[0], t[1])], edges[hex_edge_axis(t[0], t[2])], edges[hex_edge_axis(t[0], t[3])]));
}

// The vertex ids of one element: 4 for a tet, 3 for a surface triangle.
struct ElementNodes {
    std::array<Id, 4> id;
    int size;
    const Id* begin() const { return id.data(); }
    const Id* end() const { return id.data() + size; }
    Id operator[](int a) const { return id[a]; }
};

// A mesh split into tetrahedra: hexahedra, each split into its 8 corner tets, and plain tets;
// optionally with surface triangles (the 2D energy on u = 0, triangle_energy.h).
// Vertices move according to their kind: interior (free), slip (in the tangent plane of
// u = 0, then projected back by V), feature_edge (along the crease tangent, then projected
// onto the crease), corner and fixed (never). The geometry comes as functions of (vertex id,
// position), so the untangler knows nothing of how the surface is represented.
//
// Elements are numbered hex corners first: element e < 8 #hexes is corner tet e % 8
// (hex_corner_tets) of hex e / 8, whose target is the corner of an axis-aligned box with the
// hex's edge lengths along its local x, y, z; then the plain tets[e - 8 #hexes], then the
// surface triangles[e - 8 #hexes - #tets]. A hex takes 88 bytes where its 8 tets with full
// targets would take 960. A triangle's energy is measured in the tangent plane of u = 0
// whose normal is the mean of surface_normal at its three vertices (triangle_normal).
struct Problem {
    std::vector<Vec3> points;                // #V
    std::vector<VertexKind> kinds;           // #V
    std::vector<std::array<Id, 8>> hexes;    // #H, VTK node order
    std::vector<Vec3> hex_edges;             // #H, box edge lengths along x (0-1), y (0-3), z (0-4)
    std::vector<std::array<Id, 4>> tets;     // #T, vertex ids, positively oriented target
    std::vector<TetTarget> targets;          // #T
    // #R, vertex ids, counter-clockwise seen from the side surface_normal points to
    std::vector<std::array<Id, 3>> triangles;
    std::vector<TriangleTarget> triangle_targets;  // #R
    std::function<Vec3(Id, const Vec3&)> surface_normal;      // slip: normal of u = 0 (grad u)
    std::function<Vec3(Id, const Vec3&)> project_to_surface;  // slip: the projection V
    std::function<Vec3(Id, const Vec3&)> edge_tangent;        // feature_edge: crease direction
    std::function<Vec3(Id, const Vec3&)> project_to_edge;     // feature_edge: onto the crease
    double length_scale = 1;  // typical edge length: tolerances are relative to it

    Id num_elements() const { return first_triangle() + Id(triangles.size()); }
    bool is_hex_corner(Id e) const { return e < 8 * Id(hexes.size()); }
    Id first_triangle() const { return 8 * Id(hexes.size()) + Id(tets.size()); }
    bool is_triangle(Id e) const { return e >= first_triangle(); }
    // The vertex ids of element e.
    ElementNodes element(Id e) const {
        if (is_triangle(e)) {
            const auto& t = triangles[e - first_triangle()];
            return {{t[0], t[1], t[2], t[2]}, 3};
        }
        if (!is_hex_corner(e)) return {tets[e - 8 * Id(hexes.size())], 4};
        const auto& h = hexes[e / 8];
        const auto& c = hex_corner_tets[e % 8];
        return {{h[c[0]], h[c[1]], h[c[2]], h[c[3]]}, 4};
    }
    // The unit normal a triangle's energy is measured against: the normalized mean of
    // surface_normal at its vertices (NaN when they cancel).
    Vec3 triangle_normal(const std::vector<Vec3>& x, const std::array<Id, 3>& t) const {
        Vec3 n = Vec3::Zero();
        for (Id v : t) n += surface_normal(v, x[v]).normalized();
        return n / n.norm();
    }
    TetTarget target(Id e) const {
        return is_hex_corner(e) ? hex_corner_target(int(e % 8), hex_edges[e / 8]) : targets[e - 8 * Id(hexes.size())];
    }
    // The positions in x of the given vertices, as columns.
    static Mat34 corners(const std::vector<Vec3>& x, const std::array<Id, 4>& nodes) {
        Mat34 y;
        for (int a = 0; a < 4; ++a) y.col(a) = x[nodes[a]];
        return y;
    }
    static Mat3 corners(const std::vector<Vec3>& x, const std::array<Id, 3>& nodes) {
        Mat3 y;
        for (int a = 0; a < 3; ++a) y.col(a) = x[nodes[a]];
        return y;
    }
    // det S of element e at positions x (<= 0: inverted).
    double det(const std::vector<Vec3>& x, Id e) const {
        if (is_triangle(e)) {
            const Id r = e - first_triangle();
            return triangle_det(corners(x, triangles[r]), triangle_normal(x, triangles[r]), triangle_targets[r]);
        }
        return tet_det(corners(x, element(e).id), target(e));
    }
    // Adds a hex (its corner tets' targets are those of a box with the given edge lengths).
    void add_hex(const std::array<Id, 8>& nodes, const Vec3& edges) {
        hexes.push_back(nodes);
        hex_edges.push_back(edges);
    }
};

}  // namespace hexmesh::untangle

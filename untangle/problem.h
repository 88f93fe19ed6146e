// What the untangler optimizes: vertices, their constraints, and elements with targets
// (tetrahedra, and triangles on the surface u = 0).
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
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
    return box_corner_target(Vec3(edges[hex_edge_axis(t[0], t[1])],
                                  edges[hex_edge_axis(t[0], t[2])],
                                  edges[hex_edge_axis(t[0], t[3])]));
}

// A wall quad held to u = 0: the term weight u(c)^2 (unit_weight u(c)^2 when the elements
// weigh equally) with c the mean of its 4 vertices, so that the wall follows the body
// between its nodes, not only at them (a quad that bridges a limb's end or a groove costs).
struct HeldQuad {
    std::array<Id, 4> nodes{};
    double weight = 0, unit_weight = 0;
};

// The vertex ids of one element: 4 for a tet, 3 for a surface triangle.
struct ElementNodes {
    std::array<Id, 4> id{};
    int size = 4;
    const Id* begin() const { return id.data(); }
    const Id* end() const { return id.data() + size; }
    Id operator[](int a) const {
        assert(a >= 0 && a < size);
        return id[a];
    }
};

// A mesh split into tetrahedra: hexahedra, each split into its 8 corner tets, and plain tets;
// and surface triangles (the 2D energy on u = 0, triangle_energy.h), whose vertices must be
// boundary vertices (slip, feature_edge, corner or fixed: an interior vertex of a triangle
// alone would have no stiffness along the normal).
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
// whose normal is surface_normal at its centroid (triangle_normal: next to a crease, the
// normals of its vertices may all belong to the neighbouring faces). The normal moves with
// the vertices, but the gradient and Hessian hold it fixed: they are
// those of the energy in the current tangent planes, which is what a step that slides on
// u = 0 changes to first order.
struct Problem {
    std::vector<Vec3> points;              // #V
    std::vector<VertexKind> kinds;         // #V
    std::vector<std::array<Id, 8>> hexes;  // #H, VTK node order
    std::vector<Vec3> hex_edges;           // #H, box edge lengths along x (0-1), y (0-3), z (0-4)
    std::vector<std::array<Id, 4>> tets;   // #T, vertex ids, positively oriented target
    std::vector<TetTarget> targets;        // #T
    // #R, vertex ids, counter-clockwise seen from the side surface_normal points to
    std::vector<std::array<Id, 3>> triangles;
    std::vector<TriangleTarget> triangle_targets;  // #R
    // slip vertices, and triangles: normal of u = 0 (grad u) at a point near vertex id
    std::function<Vec3(Id, const Vec3&)> surface_normal;
    std::function<Vec3(Id, const Vec3&)> project_to_surface;  // slip: the projection V
    std::function<Vec3(Id, const Vec3&)> edge_tangent;        // feature_edge: crease direction
    std::function<Vec3(Id, const Vec3&)> project_to_edge;     // feature_edge: onto the crease
    // Held quads (none by default) and u, whose gradient is surface_normal's direction
    // (|grad u| close to 1 near u = 0). Not elements: no det, no target, no colour.
    std::vector<HeldQuad> held_quads;
    std::function<double(const Vec3&)> surface_value;
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
    // The unit normal a triangle's energy is measured against: surface_normal at its
    // centroid; where that turns by more than 120 degrees from the normal at its first vertex
    // (the centroid, on the chord, across a part thinner than the triangle's sag, or grad u
    // vanishing there; a crease of 90 degrees is fine), the normalized sum of its vertices'
    // normals. Zero or NaN when neither exists: the
    // triangle's energy is then NaN, and a step that leads there is rejected
    // (check_constraints refuses a problem that starts so).
    Vec3 triangle_normal(const std::vector<Vec3>& x, const std::array<Id, 3>& t) const {
        const Vec3 n0 = surface_normal(t[0], x[t[0]]).normalized();  // zero stays zero
        const Vec3 n = surface_normal(t[0], (x[t[0]] + x[t[1]] + x[t[2]]) / 3).normalized();
        if (n.dot(n0) > -0.5) return n;
        return (n0 + surface_normal(t[1], x[t[1]]).normalized() +
                surface_normal(t[2], x[t[2]]).normalized())
            .normalized();
    }
    TetTarget target(Id e) const {
        return is_hex_corner(e) ? hex_corner_target(int(e % 8), hex_edges[e / 8])
                                : targets[e - 8 * Id(hexes.size())];
    }
    // The positions in x of the given vertices, as columns (3 x 4 for a tet, 3 x 3 for a
    // triangle).
    template <size_t N>
    static Eigen::Matrix<double, 3, int(N)> corners(const std::vector<Vec3>& x,
                                                    const std::array<Id, N>& nodes) {
        Eigen::Matrix<double, 3, int(N)> y;
        for (size_t a = 0; a < N; ++a) y.col(a) = x[nodes[a]];
        return y;
    }
    // det S of element e at positions x (<= 0: inverted).
    double det(const std::vector<Vec3>& x, Id e) const {
        if (is_triangle(e)) {
            const Id r = e - first_triangle();
            return triangle_det(corners(x, triangles[r]), triangle_normal(x, triangles[r]),
                                triangle_targets[r]);
        }
        return tet_det(corners(x, element(e).id), target(e));
    }
    // Whether every vertex of element e is held (fixed or corner): nothing can change its det.
    bool held(Id e) const {
        const ElementNodes nodes = element(e);
        return std::all_of(nodes.begin(), nodes.end(),
                           [&](Id v) { return degrees_of_freedom(kinds[v]) == 0; });
    }
    // The inverted elements that are held: no solve can repair them.
    std::vector<Id> blocked_elements() const {
        std::vector<Id> blocked;
        for (Id e = 0; e < num_elements(); ++e)
            if (held(e) && !(det(points, e) > 0)) blocked.push_back(e);
        return blocked;
    }
    // Adds a hex (its corner tets' targets are those of a box with the given edge lengths).
    void add_hex(const std::array<Id, 8>& nodes, const Vec3& edges) {
        hexes.push_back(nodes);
        hex_edges.push_back(edges);
    }
    // Adds a quad (nodes in order round it) as its 4 corner triangles (c, c + 1, c + 3), each
    // with the target of a rectangle's corner: edges 0-1 and 3-2 of length `first`, 0-3 and
    // 1-2 of length `second`.
    void add_quad(const std::array<Id, 4>& q, double first, double second) {
        for (int c = 0; c < 4; ++c) {
            triangles.push_back({q[c], q[(c + 1) % 4], q[(c + 3) % 4]});
            triangle_targets.push_back(c % 2 == 0 ? rectangle_corner_target(first, second)
                                                  : rectangle_corner_target(second, first));
        }
    }
};

}  // namespace hexmesh::untangle

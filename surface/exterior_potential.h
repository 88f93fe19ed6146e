// The harmonic potential of a body's exterior in a box: 0 on the body, 1 on the box; or of its
// interior: 0 on the body, 1 on a ball inside it.
#pragma once

#include <functional>
#include <vector>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

struct ExteriorPotentialOptions {
    double margin = 0.12;       // the box: the body's bounds widened by this many longest sides
    int resolution = 96;        // nodes along the body's longest side
    double tolerance = 1e-8;    // relative residual of the linear solve
    int max_iterations = 4000;  // conjugate-gradient iterations
    // source_radius > 0: the potential of the body's interior instead, harmonic inside the body
    // between F = 0 on u = 0 and F = 1 on the ball of this radius around source_centre (which
    // must lie inside the body): its levels run from the wall (c -> 0) in to spheres round the
    // ball (c near 1), its gradient lines from every wall point to the ball. F < 0 outside the
    // body (u times the slope at the wall, as inside the body for the exterior one).
    Vec3 source_centre = Vec3::Zero();
    double source_radius = 0;
};

// F(x), harmonic in the box outside the body, F = 0 on u = 0 and 1 on the box's faces: a family
// of nested surfaces F = c from the box (c near 1, star-shaped) to the body (c -> 0) whose
// gradient lines never meet. Unlike the offsets u = d, whose sheets fuse across a gap and tear
// apart all along it at once as d falls, its levels enter the gaps between a body's parts
// gradually, from their openings (the potential decays there as e^(-pi depth / width)).
//
// Solved by finite differences on the nodes of a uniform lattice (7-point Laplacian, the body's
// boundary placed between nodes where u changes sign, by the symmetric rule of Gibou et al.
// 2002) with preconditioned conjugate gradients. Inside the body the nodes take u times the
// potential's slope at the nearest nodes outside, so the zero level of the trilinear
// interpolation lies on the body to second order. value() and gradient() interpolate
// trilinearly (the gradient piecewise, exact for the interpolant); outside the box value() is
// 1 plus the distance to it. Thread safe for concurrent calls.
//
// With options.source_radius > 0 the same for the interior: harmonic inside the body outside
// the ball, the ball's sphere placed between nodes by the same rule at value 1; outside the
// body the nodes take u times the slope, so F < 0 there, and outside the box value() is the
// value at the nearest point of the box minus the distance to it.
class ExteriorPotential : public ImplicitFunction {
  public:
    // `body` is sampled at the lattice nodes (u < 0 inside, a distance near u = 0). Throws
    // std::invalid_argument for bad options, and std::runtime_error when the solve does not
    // reach the tolerance.
    ExteriorPotential(const ImplicitFunction& body, const ExteriorPotentialOptions& options = {});

    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    Box3 bounds() const override { return box_; }

    double spacing() const { return h_; }
    int iterations() const { return iterations_; }
    long long unknowns() const { return unknowns_; }

  private:
    Box3 box_;
    double h_ = 0;
    std::array<int, 3> n_{};
    std::vector<double> values_;
    int iterations_ = 0;
    long long unknowns_ = 0;
    bool interior_ = false;  // options.source_radius > 0
};

// theta(x), the harmonic extension of a field of unit vectors into a body's exterior in a box:
// on the body (u = 0) the given `on_body` (e.g. each surface point's image under a map onto the
// sphere), on the box's faces the direction from `centre`; each of its three components solved
// as ExteriorPotential is, on the same lattice, with these Dirichlet data instead of 0 and 1.
// Its fibres {theta / |theta| = d} run from the body's point with image d out to the box's
// point in direction d from the centre and, being fibres of one map, never meet; unlike the
// gradient lines of the potential they do not part at its saddles. Inside the body the nodes
// next to it take on_body at themselves. Thread safe for concurrent calls.
class HarmonicDirections {
  public:
    // `on_body` is called concurrently. Throws as ExteriorPotential does.
    HarmonicDirections(const ImplicitFunction& body,
                       const std::function<Vec3(const Vec3&)>& on_body, const Vec3& centre,
                       const ExteriorPotentialOptions& options = {});

    Vec3 value(const Vec3& p) const;
    // Row c: the gradient of component c (trilinear, piecewise exact); zero outside the box.
    Mat3 jacobian(const Vec3& p) const;
    int iterations() const { return iterations_; }

  private:
    Box3 box_;
    double h_ = 0;
    Vec3 centre_;
    std::array<int, 3> n_{};
    std::vector<Vec3> values_;
    int iterations_ = 0;
};

}  // namespace hexmesh

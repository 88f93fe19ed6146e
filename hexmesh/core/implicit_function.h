// The implicit body interface: u(x) < 0 inside, > 0 outside, |grad u| close to 1 near u = 0.
#pragma once

#include <vector>

#include "hexmesh/core/types.h"

namespace hexmesh {

class ImplicitFunction {
  public:
    // One smooth piece of a piecewise smooth body (a box face, a cylinder cap, a CSG child's
    // piece): its own signed function at a point and that function's gradient there. Where
    // several pieces vanish together the body has a crease (2 normals) or a corner (3).
    struct Piece {
        double value;   // geometry units; < 0 on the body's side of the piece
        Vec3 gradient;  // of `value`, about unit length
    };

    virtual ~ImplicitFunction() = default;

    // Signed value at p (a signed distance where the body allows it), geometry units.
    virtual double value(const Vec3& p) const = 0;

    // Gradient of value(). The default is a central difference with step fd_step();
    // bodies with a closed form override it.
    virtual Vec3 gradient(const Vec3& p) const;

    // Appends to `out` (without clearing it) the smooth pieces whose min/max combination
    // defines the body near p and whose value at p is within `tolerance` (a length; negative
    // counts as 0) of the combination's value: on u = 0, the faces meeting at p (2 on a
    // crease, 3 or more at a corner). At least one piece. The combination's value is
    // value(p) on and inside u = 0; outside it may be smaller (outside a box edge value() is
    // the distance to the edge, the combination the larger face plane). Different CSG
    // children may contribute pieces with the same normal. The default is the smooth body:
    // the one piece {value(p), gradient(p)}.
    virtual void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const;

    // A box containing the whole body (the set u <= 0).
    virtual Box3 bounds() const = 0;

    // Step of the central differences: a small fraction of the body size.
    double fd_step() const { return 1e-6 * bounds().diagonal(); }
};

}  // namespace hexmesh

// Constructive solid geometry on implicit bodies: union, intersection, difference.
#pragma once

#include <vector>

#include "surface/body.h"

namespace hexmesh {

// Union = min, Intersection = max, Difference(a, b1, b2, ...) = max(a, -b1, -b2, ...):
// a minus every later child. With signed-distance children the result is exact outside a
// union and inside an intersection, and a lower bound of the distance elsewhere.
enum class CsgOp { Union, Intersection, Difference };

// Throws std::invalid_argument if there is no child or a child is null.
class Csg : public ImplicitFunction {
  public:
    Csg(CsgOp op, std::vector<Body> children);

    double value(const Vec3& p) const override;
    // The active child's gradient, negated for a subtracted child (index > 0 in Difference).
    Vec3 gradient(const Vec3& p) const override;
    // The pieces of every child whose value is within tolerance t of value(p) (d away),
    // collected from it with tolerance t - d; a subtracted child's pieces negated.
    void active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const override;
    // Union: hull of the children's boxes; Intersection: intersection of the boxes
    // (collapsed to a point when empty); Difference: the first child's box.
    Box3 bounds() const override;

    // Index of the child that gives value(p); ties go to the lowest index.
    int active_child(const Vec3& p) const;

    CsgOp op() const { return op_; }
    const std::vector<Body>& children() const { return children_; }

  private:
    struct Active {
        int child;
        double value;  // value(p), already negated for a subtracted child
    };
    Active evaluate(const Vec3& p) const;

    CsgOp op_;
    std::vector<Body> children_;
};

}  // namespace hexmesh

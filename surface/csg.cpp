#include "surface/csg.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hexmesh {

Csg::Csg(CsgOp op, std::vector<Body> children) : op_(op), children_(std::move(children)) {
    if (children_.empty()) throw std::invalid_argument("Csg: needs at least one child body");
    for (std::size_t i = 0; i < children_.size(); ++i)
        if (!children_[i])
            throw std::invalid_argument("Csg: child " + std::to_string(i) + " is null");
}

Csg::Active Csg::evaluate(const Vec3& p) const {
    Active best{0, children_[0]->value(p)};
    for (int i = 1; i < static_cast<int>(children_.size()); ++i) {
        const double v = children_[i]->value(p);
        switch (op_) {
            case CsgOp::Union:
                if (v < best.value) best = {i, v};
                break;
            case CsgOp::Intersection:
                if (v > best.value) best = {i, v};
                break;
            case CsgOp::Difference:
                if (-v > best.value) best = {i, -v};
                break;
        }
    }
    return best;
}

int Csg::active_child(const Vec3& p) const {
    return evaluate(p).child;
}

double Csg::value(const Vec3& p) const {
    return evaluate(p).value;
}

Vec3 Csg::gradient(const Vec3& p) const {
    const int i = evaluate(p).child;
    const Vec3 g = children_[i]->gradient(p);
    return (op_ == CsgOp::Difference && i > 0) ? Vec3(-g) : g;
}

void Csg::active_pieces(const Vec3& p, double tolerance, std::vector<Piece>& out) const {
    const int n = static_cast<int>(children_.size());
    std::vector<double> values(n);  // negated for a subtracted child
    for (int i = 0; i < n; ++i) {
        const double v = children_[i]->value(p);
        values[i] = (op_ == CsgOp::Difference && i > 0) ? -v : v;
    }
    const double u = op_ == CsgOp::Union ? *std::min_element(values.begin(), values.end())
                                         : *std::max_element(values.begin(), values.end());
    for (int i = 0; i < n; ++i) {
        const double slack = std::max(tolerance, 0.0) - std::abs(values[i] - u);
        if (!(slack >= 0)) continue;
        const std::size_t first = out.size();
        children_[i]->active_pieces(p, slack, out);
        if (op_ != CsgOp::Difference || i == 0) continue;
        for (std::size_t k = first; k < out.size(); ++k) {
            out[k].value = -out[k].value;
            out[k].gradient = -out[k].gradient;
        }
    }
}

Box3 Csg::bounds() const {
    Box3 b = children_[0]->bounds();
    if (op_ == CsgOp::Difference) return b;
    for (std::size_t i = 1; i < children_.size(); ++i) {
        const Box3 c = children_[i]->bounds();
        if (op_ == CsgOp::Union) {
            b.lo = b.lo.cwiseMin(c.lo);
            b.hi = b.hi.cwiseMax(c.hi);
        } else {
            b.lo = b.lo.cwiseMax(c.lo);
            b.hi = b.hi.cwiseMin(c.hi);
        }
    }
    b.hi = b.hi.cwiseMax(b.lo);
    return b;
}

}  // namespace hexmesh

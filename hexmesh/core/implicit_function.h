// The implicit body interface: u(x) < 0 inside, > 0 outside, |grad u| close to 1 near u = 0.
#pragma once

#include "hexmesh/core/types.h"

namespace hexmesh {

class ImplicitFunction {
public:
    virtual ~ImplicitFunction() = default;

    // Signed value at p (a signed distance where the body allows it), geometry units.
    virtual double value(const Vec3& p) const = 0;

    // Gradient of value(). The default is a central difference with step fd_step();
    // bodies with a closed form override it.
    virtual Vec3 gradient(const Vec3& p) const;

    // A box containing the whole body (the set u <= 0).
    virtual Box3 bounds() const = 0;

    // Step of the central differences: a small fraction of the body size.
    double fd_step() const { return 1e-6 * bounds().diagonal(); }
};

}  // namespace hexmesh

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

Vec3 ImplicitFunction::gradient(const Vec3& p) const {
    const double h = fd_step();
    Vec3 g;
    for (int a = 0; a < 3; ++a) {
        Vec3 e = Vec3::Zero();
        e[a] = h;
        g[a] = (value(p + e) - value(p - e)) / (2 * h);
    }
    return g;
}

void ImplicitFunction::active_pieces(const Vec3& p, double /*tolerance*/,
                                     std::vector<Piece>& out) const {
    out.push_back({value(p), gradient(p)});
}

}  // namespace hexmesh

#include "volume/wall_lines.h"

#include <algorithm>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace hexmesh {

std::vector<WallFace> wall_faces(const Block& b) {
    std::vector<WallFace> faces;
    for (int f = imin; f <= kmax; ++f) {
        const int axis = f / 2, p = axis == 0 ? 1 : 0, q = axis == 2 ? 1 : 2;
        if (b.face_patch[f] != "wall" || b.nodes[axis] < 2) continue;
        faces.push_back({&b, axis, f % 2 == 1, p, q, b.nodes[p], b.nodes[q], b.nodes[axis]});
    }
    return faces;
}

std::vector<WallFace> wall_faces(const BlockGrid& grid) {
    std::vector<WallFace> faces;
    for (const Block& b : grid.blocks)
        for (const WallFace& f : wall_faces(b)) faces.push_back(f);
    return faces;
}

double grid_side(const WallFace& f, const std::vector<Vec3>& points, const ImplicitFunction& body) {
    const int t = std::max(1, (f.depth - 1) / 2);
    const Id balance = tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, f.lines()), Id(0),
        [&](const tbb::blocked_range<Id>& r, Id sum) {
            for (Id l = r.begin(); l != r.end(); ++l) {
                const double u = body.value(points[f.node(int(l % f.np), int(l / f.np), t)]);
                sum += (u > 0) - (u < 0);
            }
            return sum;
        },
        [](Id a, Id b) { return a + b; });
    return balance < 0 ? -1.0 : 1.0;
}

}  // namespace hexmesh

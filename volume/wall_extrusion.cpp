#include "volume/wall_extrusion.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "volume/wall_lines.h"

namespace hexmesh {

std::vector<bool> crossed_lines(const BlockGrid& grid, const std::vector<WallFace>& faces) {
    constexpr Id nobody = -1;
    std::vector<Id> start(grid.points.size(), nobody);
    std::vector<bool> crossed(grid.points.size(), false);
    for (const WallFace& f : faces)
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                const Id s = f.node(p, q, 0);
                for (int m = 0; m < f.depth - 1; ++m) {  // from the wall node: it must not move
                    Id& owner = start[f.node(p, q, m)];
                    if (owner == nobody)
                        owner = s;
                    else if (owner != s)
                        crossed[f.node(p, q, m)] = true;
                }
            }
    return crossed;
}

double line_length(const BlockGrid& grid, const WallFace& f, int p, int q) {
    double length = 0;
    for (int m = 1; m < f.depth; ++m)
        length += (grid.points[f.node(p, q, m)] - grid.points[f.node(p, q, m - 1)]).norm();
    return length;
}

ThinWallLines thin_wall_lines(const BlockGrid& grid, const WallLayers& law) {
    ThinWallLines thin;
    thin.fewest = law.layers;
    if (law.layers <= 0) return thin;
    for (const WallFace& f : wall_faces(grid))
        for (int q = 0; q < f.nq; ++q)
            for (int p = 0; p < f.np; ++p) {
                ++thin.lines;
                const double length = line_length(grid, f, p, q);
                const int m = layers_that_fit(length, f.depth - 1, law);
                if (m >= law.layers) continue;
                ++thin.cut;
                if (m < thin.fewest || (m == thin.fewest && length < thin.length)) {
                    thin.fewest = m;
                    thin.length = length;
                    thin.wall = grid.points[f.node(p, q, 0)];
                }
            }
    return thin;
}

std::vector<bool> extrude_wall_layers(BlockGrid& grid, const ImplicitFunction& body,
                                      const WallLayers& law, int blend) {
    std::vector<bool> placed(grid.points.size(), false);
    if (law.layers <= 0) return placed;
    const std::vector<double> d = layer_heights(law);

    const std::vector<WallFace> faces = wall_faces(grid);
    const std::vector<bool> crossed = crossed_lines(grid, faces);
    for (const WallFace& f : faces) {
        const double side = grid_side(f, grid.points, body);
        const int last = f.depth - 1;
        // Lines left after crossed_lines share nodes only where they coincide (block
        // interfaces), and then they compute the same positions: the parallel writes agree.
        std::vector<int> laid(f.lines(), 0);  // nodes laid, the wall node included
        tbb::parallel_for(Id(0), f.lines(), [&](Id l) {
            const int p = int(l % f.np), q = int(l / f.np);
            for (int m = 1; m < last; ++m)
                if (crossed[f.node(p, q, m)]) return;
            const int layers = layers_that_fit(line_length(grid, f, p, q), last, law);
            if (layers <= 0) return;
            const Vec3 x0 = grid.points[f.node(p, q, 0)];
            const std::optional<Vec3> n = unit_offset(body, x0, side, 1e-3 * law.first_height);
            if (!n) return;
            const Vec3 shift = x0 + d[layers] * *n - grid.points[f.node(p, q, layers)];
            for (int m = 1; m <= layers; ++m) grid.points[f.node(p, q, m)] = x0 + d[m] * *n;
            const int end = blend > 0 ? std::min(last, layers + blend + 1) : last;  // shift 0 there
            for (int m = layers + 1; m < end; ++m)
                grid.points[f.node(p, q, m)] += shift * (double(end - m) / (end - layers));
            laid[l] = layers + 1;
        });
        for (Id l = 0; l < f.lines(); ++l)
            for (int m = 0; m < laid[l]; ++m)
                placed[f.node(int(l % f.np), int(l / f.np), m)] = true;
    }
    return placed;
}

}  // namespace hexmesh

#include "volume/wall_extrusion.h"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>

#include "volume/wall_lines.h"

namespace hexmesh {

std::vector<bool> extrude_wall_layers(BlockGrid& grid, const ImplicitFunction& body,
                                      const WallLayers& law) {
    std::vector<bool> placed(grid.points.size(), false);
    if (law.layers <= 0) return placed;
    std::vector<double> d(law.layers + 1, 0.0);
    for (int m = 1; m <= law.layers; ++m)
        d[m] = d[m - 1] + law.first_height * std::pow(law.growth_ratio, m - 1);

    for (const WallFace& f : wall_faces(grid)) {
        const double side = grid_side(f, grid.points, body);
        const int last = f.depth - 1, layers = std::min(law.layers, last - 1);
        // Lines of different faces share nodes only where they coincide (block interfaces),
        // and then they compute the same positions: the parallel writes agree.
        tbb::parallel_for(Id(0), f.lines(), [&](Id l) {
            const int p = int(l % f.np), q = int(l / f.np);
            const Id wall = f.node(p, q, 0);
            if (grid.kinds[wall] != VertexKind::slip) return;  // creases have no single normal
            const Vec3 x0 = grid.points[wall];
            const Vec3 g = body.gradient(x0);
            if (!(g.norm() > 0)) return;
            const Vec3 n = side * g.normalized();
            const Vec3 shift = x0 + d[layers] * n - grid.points[f.node(p, q, layers)];
            for (int m = 1; m <= layers; ++m) grid.points[f.node(p, q, m)] = x0 + d[m] * n;
            for (int m = layers + 1; m < last; ++m)
                grid.points[f.node(p, q, m)] += shift * (double(last - m) / (last - layers));
        });
        for (Id l = 0; l < f.lines(); ++l)
            if (grid.kinds[f.node(int(l % f.np), int(l / f.np), 0)] == VertexKind::slip)
                for (int m = 0; m <= layers; ++m)
                    placed[f.node(int(l % f.np), int(l / f.np), m)] = true;
    }
    return placed;
}

}  // namespace hexmesh

// The nodes of grid lines laid along a continuation's paths (volume/wall_paths.h): a boundary
// layer from the wall, the next layers on the paths' levels, the rest on to a node beyond.
#pragma once

#include <functional>
#include <vector>

#include "volume/stretching.h"
#include "volume/wall_paths.h"

namespace hexmesh {

// The nk + 1 nodes of every path's line, handed to set_line(s, x) (in parallel, once per
// path s): x[0] = wall[s] (the path's first point replaced by it), the boundary layer of `law`
// (at most nk - 2 cells) by arc length along the path, then up to the path's end (x[k_far])
// on levels evenly spaced in log F from the one at the top of the boundary layer to
// paths.far_level, then geometric from the last of those cells' height on to x[nk] = far[s].
// k_far is the same for every line: of the nk - m cells beyond the layer, the share the
// levels take of the growth-ratio steps each part spans on a typical line. The surfaces of
// equal level are nested, so neighbouring lines' nodes of one k lie on one level.
void place_nodes_on_paths(const WallPaths& paths, const std::vector<Vec3>& wall,
                          const std::vector<Vec3>& far, int nk, const WallLayers& law,
                          const std::function<void(Id s, const std::vector<Vec3>& x)>& set_line);

}  // namespace hexmesh

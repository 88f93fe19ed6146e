// The shape of an exterior grid's far-field boundary, shared by the case file and the O-grid.
#pragma once

namespace hexmesh {

enum class FarFieldShape { sphere, box };  // a sphere of radius `size`, a cube of half-size `size`

}  // namespace hexmesh

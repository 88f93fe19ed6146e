// Per-vertex constraint kinds: how the optimizer may move each vertex.
#pragma once

#include <cstdint>
#include <string_view>

namespace hexmesh {

// interior: free in 3D; slip: slides on u = 0 (2 dof); feature_edge: slides along a sharp
// crease of the body (1 dof); corner: a body corner, fixed; fixed: never moves.
enum class VertexKind : std::uint8_t { interior, slip, feature_edge, corner, fixed };

constexpr int degrees_of_freedom(VertexKind kind) {
    switch (kind) {
        case VertexKind::interior:
            return 3;
        case VertexKind::slip:
            return 2;
        case VertexKind::feature_edge:
            return 1;
        case VertexKind::corner:
        case VertexKind::fixed:
            return 0;
    }
    return 0;
}

constexpr std::string_view to_string(VertexKind kind) {
    switch (kind) {
        case VertexKind::interior:
            return "interior";
        case VertexKind::slip:
            return "slip";
        case VertexKind::feature_edge:
            return "feature_edge";
        case VertexKind::corner:
            return "corner";
        case VertexKind::fixed:
            return "fixed";
    }
    return "?";
}

}  // namespace hexmesh

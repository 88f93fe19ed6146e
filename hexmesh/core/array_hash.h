// Hash of a fixed-size array, for unordered_map keys such as the sorted node ids of an edge or
// face, or a point's exact coordinates.
#pragma once

#include <array>
#include <cstddef>
#include <functional>

namespace hexmesh {

template <class T, std::size_t N>
struct ArrayHash {
    std::size_t operator()(const std::array<T, N>& key) const {
        std::size_t h = 0;
        for (const T& v : key) h = h * 0x9E3779B97F4A7C15ull + std::hash<T>()(v);
        return h;
    }
};

}  // namespace hexmesh

// Test support: the bodies of bench/random_bodies.py (cores with bent limbs), generated where a
// test needs them.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace hexmesh::test {

// Whether bench/random_bodies.py can run here (/usr/bin/python3 with Debian's python3-vtk9).
inline bool random_bodies_available() {
    return std::system("/usr/bin/python3 -c 'import vtk, numpy' > /dev/null 2>&1") == 0;
}

// The command that writes the first `count` bodies of `seed` into `dir`
// (dir/random<seed>_01.stl ...); run it with std::system, 0 when written.
inline std::string random_bodies_command(const std::filesystem::path& dir, int count, int seed) {
    return "/usr/bin/python3 '" HEXMESH_SOURCE_DIR "/bench/random_bodies.py' '" + dir.string() +
           "' --count " + std::to_string(count) + " --seed " + std::to_string(seed) +
           " > /dev/null";
}

// Body k (from 1) of `seed` in a directory random_bodies_command wrote.
inline std::filesystem::path random_body(const std::filesystem::path& dir, int seed, int k) {
    return dir / ("random" + std::to_string(seed) + "_" + (k < 10 ? "0" : "") + std::to_string(k) +
                  ".stl");
}

}  // namespace hexmesh::test

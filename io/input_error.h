// Bad user input, and the file it came from: the one error every reader and the case schema
// throw, so that the command line prints one line and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace hexmesh {

// Bad user input: the message names the file, key or line and what was expected.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// f(), with a std::invalid_argument it throws (content of `file` the code cannot take: a face
// shared by three cells, a voxel size too fine) turned into an InputError naming the file.
template <class F>
decltype(auto) naming_file(const std::string& file, F&& f) {
    try {
        return f();
    } catch (const std::invalid_argument& e) {
        throw InputError(file + ": " + e.what());
    }
}

}  // namespace hexmesh

// libFuzzer target of one of hexmesh's file readers, chosen at build time (FUZZ_READER): the
// input is written to a file with the reader's extension and read. A refusal (any exception)
// is a correct answer; a crash, a sanitizer report, a leak or a hang is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <fstream>
#include <string>

#include "io/case_file.h"
#include "io/gmsh_mesh.h"
#include "io/medit_mesh.h"
#include "io/plot3d.h"
#include "io/sample_readers.h"
#include "io/surface_reader.h"
#include "io/volume_mesh_io.h"
#include "io/vtk_mesh.h"

namespace {

// The file the input goes to: one per process, in the temporary folder.
std::string file_with(const char* extension) {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp ? tmp : "/tmp") + "/hexmesh_fuzz_" + std::to_string(::getpid()) +
           extension;
}

template <class Read>
void read_as(const char* extension, const uint8_t* data, size_t size, Read read) {
    const std::string path = file_with(extension);
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    try {
        read(path);
    } catch (const std::exception&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace hexmesh;
#if FUZZ_READER == 1  // surfaces: the first byte picks the format
    if (size == 0) return 0;
    static const char* const extensions[] = {".stl", ".obj", ".off", ".ply"};
    read_as(extensions[data[0] % 4], data + 1, size - 1,
            [](const std::string& p) { read_surface(p); });
#elif FUZZ_READER == 2
    read_as(".json", data, size, [](const std::string& p) { read_case(p); });
#elif FUZZ_READER == 3  // legacy VTK, through both mesh readers
    read_as(".vtk", data, size, [](const std::string& p) { read_vtk_mesh(p); });
    read_as(".vtk", data, size, [](const std::string& p) { read_volume_mesh(p); });
#elif FUZZ_READER == 4
    read_as(".msh", data, size, [](const std::string& p) { read_gmsh_mesh(p); });
#elif FUZZ_READER == 5
    read_as(".mesh", data, size, [](const std::string& p) { read_medit_mesh(p); });
#elif FUZZ_READER == 6
    read_as(".xyz", data, size, [](const std::string& p) { read_plot3d(p); });
#elif FUZZ_READER == 7  // point clouds: .xyz or .ply by the first byte
    if (size == 0) return 0;
    read_as(data[0] % 2 ? ".xyz" : ".ply", data + 1, size - 1,
            [](const std::string& p) { read_point_cloud(p); });
#elif FUZZ_READER == 8
    read_as(".sections", data, size, [](const std::string& p) { read_sections(p); });
#elif FUZZ_READER == 9   // VTK XML structured grids, through the block-grid reader
    read_as(".vts", data, size, [](const std::string& p) { read_vtk_block_grid(p); });
#elif FUZZ_READER == 10  // VTK XML unstructured grids, through both mesh readers
    read_as(".vtu", data, size, [](const std::string& p) { read_vtk_mesh(p); });
    read_as(".vtu", data, size, [](const std::string& p) { read_volume_mesh(p); });
#else
#error \
    "FUZZ_READER: 1 surface, 2 case, 3 vtk, 4 gmsh, 5 medit, 6 plot3d, 7 points, 8 sections, 9 vts, 10 vtu"
#endif
    return 0;
}

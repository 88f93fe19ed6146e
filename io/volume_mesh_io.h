// Unstructured volume meshes (hexahedra and tetrahedra) in files: VTK legacy and XML, Medit.
#pragma once

#include <string>

#include "hexmesh/core/hex_mesh.h"

namespace hexmesh {

// Reads the hexahedra (voxels reordered), tetrahedra and the point array "fixed" (any
// numeric type, non-zero = fixed) of a .vtk or .vtu file, or the hexahedra of a Medit .mesh.
// Lower-dimensional cells (boundary faces, edges) are skipped. Throws InputError naming the
// file for a missing or unreadable file, other 3D cell types, or no volume cell at all.
VolumeMesh read_volume_mesh(const std::string& path);

// Writes `mesh` as .vtu (VTK XML) or .vtk (legacy), with the "fixed" array when present,
// through a temporary file renamed at the end. Throws std::runtime_error on failure.
void write_volume_mesh(const VolumeMesh& mesh, const std::string& path);

// Throws InputError unless `path` has a writable format and its folder exists: checked
// before a long run so that it cannot fail at the end.
void check_volume_mesh_output(const std::string& path);

}  // namespace hexmesh

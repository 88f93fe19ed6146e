// Private to io/: VTK writers and filters with their messages turned into our errors, and the
// checks the mesh readers share.
#pragma once

#include <vtkDataObject.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkXMLWriterBase.h>

#include <string>

#include "hexmesh/core/types.h"

namespace hexmesh::vtk_support {

// The first VTK error or warning since the last call, without VTK's "vtkClass (0x...): "
// prefix ("" if none). The first call routes VTK's messages away from the terminal.
std::string take_message();

// Lower-case extension of `path`, with its dot (".vtu").
std::string extension(const std::string& path);

// Throws std::runtime_error naming the file when a VTK writer's Write() failed or complained.
void check_written(int status, const std::string& path);

// Sets an XML writer up for speed: appended raw binary data, no base64, no compression
// (double-precision coordinates and Jacobians hardly compress: on a 10 M-cell grid LZ4
// saves 30 % of the size for 30 % more write time, zlib 40 % for 10x the time), 64-bit
// headers for arrays over 4 GB. ParaView and VTK readers read it as any other XML file.
void configure_xml_writer(vtkXMLWriterBase& writer);

// Throws InputError naming the file and cell when the cell has fewer than `count` point ids
// (what its type takes) or any of them is outside [0, points).
void check_cell_points(vtkIdList* ids, int count, Id points, const std::string& path,
                       vtkIdType cell);

// Throws InputError "PATH: no such mesh file" unless `path` is a regular file.
void require_file(const std::string& path);

}  // namespace hexmesh::vtk_support

// Private to io/: running VTK readers and writers with their messages turned into our errors.
#pragma once

#include <string>

#include "hexmesh/core/types.h"
#include <vtkDataObject.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkXMLWriterBase.h>

namespace hexmesh::vtk_support {

// The first VTK error or warning since the last call, without VTK's "vtkClass (0x...): "
// prefix ("" if none). The first call routes VTK's messages away from the terminal.
std::string take_message();

// Lower-case extension of `path`, with its dot (".vtu").
std::string extension(const std::string& path);

// Runs a VTK reader on `path`; throws InputError naming the file with VTK's message when it
// fails. The file must exist (checked first, with its own message).
template <class Reader>
vtkSmartPointer<vtkDataObject> read_with(const std::string& path);

// Throws std::runtime_error naming the file when a VTK writer's Write() failed or complained.
void check_written(int status, const std::string& path);

// Sets an XML writer up for speed: appended raw binary data, no base64, no compression
// (double-precision coordinates and Jacobians hardly compress: on a 10 M-cell grid LZ4
// saves 30 % of the size for 30 % more write time, zlib 40 % for 10x the time), 64-bit
// headers for arrays over 4 GB. ParaView and VTK readers read it as any other XML file.
void configure_xml_writer(vtkXMLWriterBase& writer);

// Throws InputError naming the file and cell when the cell has fewer than `count` point ids
// (what its type takes) or any of them is outside [0, points).
void check_cell_points(vtkIdList* ids, int count, Id points, const std::string& path, vtkIdType cell);

// Checks an XML VTK file (.vts, .vtu; a .vtm's pieces) before VTK's XML reader sees it: its
// header_type and byte_order, a structured file's extents (six integers, ranges ascending,
// pieces inside the whole), that the sections of arrays (FieldData, PointData, ...) hold arrays
// only, every array's type (one VTK knows), that point and cell arrays hold one value for each
// point or cell of their piece (points: 3 components), and that every array stored in raw appended data (its byte
// count, or its compressed block table) lies inside that data: VTK 9.1's reader runs off the
// end (a crash) on a string array whose byte count is garbage, or that holds another number of
// strings than it declares, or whose last string is not terminated. Throws InputError naming the
// file, the array and the fault; returns quietly for inline and base64 data.
void check_xml_vtk(const std::string& path);

void require_file(const std::string& path);
[[noreturn]] void throw_read_error(const std::string& path, const std::string& why);

template <class Reader>
vtkSmartPointer<vtkDataObject> read_with(const std::string& path) {
    require_file(path);
    take_message();
    vtkNew<Reader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkSmartPointer<vtkDataObject> out = reader->GetOutputDataObject(0);
    const std::string why = take_message();
    if (!why.empty() || !out) throw_read_error(path, why.empty() ? "no data" : why);
    return out;
}

}  // namespace hexmesh::vtk_support

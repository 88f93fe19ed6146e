// Private to io/: VTK XML files (.vts, .vtu, .vtm) read by a parser of our own that checks every
// count, offset, size and id before anything is sized from it (VTK 9.1's XML reader runs off
// its buffers on files it does not check).
#pragma once

#include <vtkDataObject.h>
#include <vtkSmartPointer.h>

#include <string>

namespace hexmesh {

// Reads a VTK XML file by the type its <VTKFile> names: a StructuredGrid (one piece) as a
// vtkStructuredGrid, an UnstructuredGrid (one piece; polyhedra refused) as a
// vtkUnstructuredGrid, a vtkMultiBlockDataSet as a vtkMultiBlockDataSet of its pieces' data sets
// (.vts or .vtu files beside it; nested blocks flattened in file order, each with its `name`).
// Data in any of VTK's layouts: ascii, inline base64 ("binary"), appended raw or base64;
// headers UInt32 or UInt64, either byte order, uncompressed or compressed (zlib, LZ4, LZMA).
// Point, cell and field arrays of every numeric type and of strings are kept. Throws InputError
// naming the file, the element or array and the fault: malformed XML, an attribute or extent
// that is not what VTK writes, an array whose values are not one per point or cell of its
// piece (times its components), a byte count, block table or offset that runs past the data, a
// block that does not decompress to its size, a size beyond the memory limit, a non-finite
// coordinate, a cell list whose offsets do not add up or whose ids lie outside the points, a
// cell type VTK does not know.
vtkSmartPointer<vtkDataObject> read_xml_vtk(const std::string& path);

}  // namespace hexmesh

// Private to io/: legacy VTK files (.vtk) read by a parser of our own that checks every count,
// id and value before anything is sized from it (VTK's legacy reader does not).
#pragma once

#include <vtkDataSet.h>
#include <vtkSmartPointer.h>

#include <string>

namespace hexmesh {

// Reads a legacy VTK file, ASCII or BINARY (big-endian), of versions 1.0 to 5.1: an
// UNSTRUCTURED_GRID (POINTS, CELLS, CELL_TYPES; cell lists as rows "n id ..." before version 5,
// as OFFSETS and CONNECTIVITY from 5.0 on) as a vtkUnstructuredGrid, or a STRUCTURED_GRID
// (DIMENSIONS, POINTS) as a vtkStructuredGrid. POINTS may be of any numeric type. Of the
// attributes only the first point array named `point_array` is kept (as doubles, with its
// components), if that name is given and the file has one; every other array (POINT_DATA,
// CELL_DATA, FIELD, LOOKUP_TABLE; strings too) and METADATA block is checked to fit in the
// file and skipped. Throws InputError naming the file, the line (ASCII) or byte (binary) and
// the fault: a count the rest of the file cannot hold, a cell list whose rows or offsets do
// not add up to its declared size, a point id outside the points, a cell type VTK does not
// know, a non-finite coordinate, a POINT_DATA or CELL_DATA count that is not the data set's.
vtkSmartPointer<vtkDataSet> read_legacy_vtk(const std::string& path,
                                            const std::string& point_array = "");

}  // namespace hexmesh

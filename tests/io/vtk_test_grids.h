// Test support for the VTK readers: small data sets written with VTK's own writers.
#pragma once

#include <vtkCellType.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

namespace hexmesh::test {

// Two hexahedra stacked along z (points 0-11), a tetrahedron on top of them (with point 12 at
// (0.5, 0.25, 4)) and a triangle on the bottom face, in that cell order: hex, triangle, hex,
// tet. Points of `point_type` (VTK_FLOAT or VTK_DOUBLE).
inline vtkSmartPointer<vtkUnstructuredGrid> two_hexes_a_tet_and_a_triangle(int point_type) {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    vtkNew<vtkPoints> points;
    points->SetDataType(point_type);
    for (int c = 0; c < 12; ++c)
        points->InsertNextPoint(0.25 * (c & 1), (c >> 1) & 1, 1.5 * (c >> 2));
    points->InsertNextPoint(0.5, 0.25, 4.0);
    grid->SetPoints(points);
    const vtkIdType hex0[8] = {0, 1, 3, 2, 4, 5, 7, 6}, hex1[8] = {4, 5, 7, 6, 8, 9, 11, 10};
    const vtkIdType tet[4] = {8, 9, 10, 12}, face[3] = {0, 1, 2};
    grid->InsertNextCell(VTK_HEXAHEDRON, 8, hex0);
    grid->InsertNextCell(VTK_TRIANGLE, 3, face);
    grid->InsertNextCell(VTK_HEXAHEDRON, 8, hex1);
    grid->InsertNextCell(VTK_TETRA, 4, tet);
    return grid;
}

}  // namespace hexmesh::test

#include "hexmesh/pipeline/body_surface.h"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <cmath>
#include <stdexcept>

#include "hexmesh/core/deterministic_for.h"
#include "surface/surface_diagnostics.h"

namespace hexmesh {

TriangleSurface contour_body(const ImplicitFunction& body, int cells) {
    const Box3 box = body.bounds();
    const double step = box.size().maxCoeff() / cells;
    if (!(step > 0)) throw std::invalid_argument("contour_body: the body's bounds are empty");
    const Vec3 origin = box.lo - Vec3::Constant(2 * step);
    int n[3];
    for (int a = 0; a < 3; ++a) n[a] = int(std::ceil(box.size()[a] / step)) + 5;  // nodes
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(n[0], n[1], n[2]);
    // VTK keeps the contour's points in single precision: the lattice is placed at the origin
    // and moved back in double, so a body far from the origin keeps its digits.
    image->SetOrigin(0, 0, 0);
    image->SetSpacing(step, step, step);
    auto values = vtkSmartPointer<vtkFloatArray>::New();
    values->SetNumberOfValues(vtkIdType(n[0]) * n[1] * n[2]);
    float* u = values->GetPointer(0);
    // VTK's point order: x fastest, then y, then z. The padding keeps u = 0 off the lattice's
    // faces, so the contour closes.
    deterministic_for(Id(n[2]), [&](Id k) {
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                const Vec3 x = origin + step * Vec3(i, j, double(k));
                u[(k * n[1] + j) * n[0] + i] = float(body.value(x));
            }
    });
    image->GetPointData()->SetScalars(values);
    auto contour = vtkSmartPointer<vtkFlyingEdges3D>::New();
    contour->SetInputData(image);
    contour->SetValue(0, 0.0);
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOff();
    contour->Update();
    vtkPolyData* out = contour->GetOutput();
    TriangleSurface s;
    s.points.reserve(size_t(out->GetNumberOfPoints()));
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p) {
        double x[3];
        out->GetPoint(p, x);
        s.points.push_back(origin + Vec3(x[0], x[1], x[2]));
    }
    vtkCellArray* polys = out->GetPolys();
    polys->InitTraversal();
    vtkIdType count = 0;
    const vtkIdType* ids = nullptr;
    while (polys->GetNextCell(count, ids))
        if (count == 3) s.triangles.push_back({int(ids[0]), int(ids[1]), int(ids[2])});
    if (s.triangles.empty())
        throw std::invalid_argument(fmt::format(
            "no surface u = 0 on a lattice of {:.3g} cells: no point of the body is inside, or "
            "it is thinner than that",
            step));
    long long removed = 0;
    std::optional<TriangleSurface> clean = without_zero_area_triangles(s, removed);
    const auto closed = [](const TriangleSurface& t) {
        for (const auto& [edge, uses] : edge_uses(t.triangles))
            if (uses != 2) return false;
        return true;
    };
    if (!clean || !closed(*clean))
        throw std::invalid_argument(
            "its contour u = 0 is not a closed manifold surface (parts of the body touch within "
            "a lattice cell)");
    if (signed_volume(*clean, box.center()) < 0)
        for (auto& t : clean->triangles) std::swap(t[1], t[2]);
    return std::move(*clean);
}

}  // namespace hexmesh

#include "io/volume_mesh_io.h"

#include <fmt/format.h>
#include <unistd.h>
#include <vtkCell.h>
#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <filesystem>

#include "io/input_error.h"
#include "io/legacy_vtk.h"
#include "io/medit_mesh.h"
#include "io/vtk_support.h"
#include "io/xml_vtk.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

VolumeMesh from_vtk(vtkDataSet* data, const std::string& path) {
    VolumeMesh mesh;
    mesh.points.resize(data->GetNumberOfPoints());
    for (vtkIdType m = 0; m < data->GetNumberOfPoints(); ++m) {
        double x[3];
        data->GetPoint(m, x);
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
            throw InputError(fmt::format("{}: point {} has a non-finite coordinate", path, m));
        mesh.points[m] = Vec3(x[0], x[1], x[2]);
    }
    vtkNew<vtkIdList> ids;
    static constexpr int voxel_to_hex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
        const int type = data->GetCellType(c);
        data->GetCellPoints(c, ids);
        // Every cell's ids in range before VTK builds any cell from them (GetCell reads points).
        const int takes = type == VTK_TETRA                             ? 4
                          : type == VTK_HEXAHEDRON || type == VTK_VOXEL ? 8
                                                                        : 0;
        vtk_support::check_cell_points(ids, takes, Id(mesh.points.size()), path, c);
        if (type == VTK_HEXAHEDRON || type == VTK_VOXEL) {
            for (int v = 0; v < 8; ++v)
                mesh.hexes.push_back(ids->GetId(type == VTK_VOXEL ? voxel_to_hex[v] : v));
        } else if (type == VTK_TETRA) {
            for (int v = 0; v < 4; ++v) mesh.tets.push_back(ids->GetId(v));
        } else if (vtkCell* cell = data->GetCell(c); !cell || cell->GetCellDimension() == 3) {
            // Types VTK names but builds no cell of (parametric, some higher-order): refused.
            throw InputError(
                fmt::format("{}: cell {} has VTK type {}; only hexahedra and tetrahedra "
                            "are supported",
                            path, c, type));
        }
    }
    if (mesh.hexes.empty() && mesh.tets.empty())
        throw InputError(fmt::format("{}: the file holds no hexahedron or tetrahedron", path));
    if (vtkDataArray* fixed = data->GetPointData()->GetArray("fixed")) {
        if (fixed->GetNumberOfTuples() != vtkIdType(mesh.points.size()))
            throw InputError(
                fmt::format("{}: the point array \"fixed\" has {} values for {} points", path,
                            fixed->GetNumberOfTuples(), mesh.points.size()));
        mesh.fixed.resize(mesh.points.size());
        for (vtkIdType m = 0; m < fixed->GetNumberOfTuples(); ++m)
            mesh.fixed[m] = fixed->GetComponent(m, 0) != 0;
    }
    return mesh;
}

vtkSmartPointer<vtkUnstructuredGrid> to_vtk(const VolumeMesh& mesh) {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(Id(mesh.points.size()));
    for (size_t m = 0; m < mesh.points.size(); ++m) points->SetPoint(m, mesh.points[m].data());
    grid->SetPoints(points);
    grid->Allocate(mesh.num_hexes() + mesh.num_tets());
    for (Id c = 0; c < mesh.num_hexes(); ++c) {
        vtkIdType ids[8];
        for (int v = 0; v < 8; ++v) ids[v] = mesh.hexes[8 * c + v];
        grid->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
    }
    for (Id c = 0; c < mesh.num_tets(); ++c) {
        vtkIdType ids[4];
        for (int v = 0; v < 4; ++v) ids[v] = mesh.tets[4 * c + v];
        grid->InsertNextCell(VTK_TETRA, 4, ids);
    }
    if (!mesh.fixed.empty()) {
        vtkNew<vtkUnsignedCharArray> fixed;
        fixed->SetName("fixed");
        fixed->SetNumberOfValues(Id(mesh.fixed.size()));
        for (size_t m = 0; m < mesh.fixed.size(); ++m) fixed->SetValue(m, mesh.fixed[m]);
        grid->GetPointData()->AddArray(fixed);
    }
    return grid;
}

}  // namespace

VolumeMesh read_volume_mesh(const std::string& path) {
    const std::string ext = vtk_support::extension(path);
    if (ext == ".mesh") {
        const HexMesh hexes = read_medit_mesh(path);
        return VolumeMesh{hexes.points, hexes.hexes, {}, {}};
    }
    vtkSmartPointer<vtkDataObject> data;
    if (ext == ".vtk") {
        data = read_legacy_vtk(path, "fixed");
    } else if (ext == ".vtu") {
        data = read_xml_vtk(path);
    } else
        throw InputError(fmt::format(
            "{}: unknown volume mesh format '{}' (expected .vtk, .vtu or .mesh)", path, ext));
    auto* set = vtkDataSet::SafeDownCast(data);
    if (!set) throw InputError(fmt::format("{}: not a VTK data set", path));
    return from_vtk(set, path);
}

void check_volume_mesh_output(const std::string& path) {
    const std::string ext = vtk_support::extension(path);
    if (ext != ".vtu" && ext != ".vtk")
        throw InputError(fmt::format("{}: cannot write '{}' meshes (use .vtu or .vtk)", path, ext));
    const fs::path folder = fs::absolute(path).parent_path();
    std::error_code ec;
    if (!fs::is_directory(folder, ec) || ::access(folder.c_str(), W_OK) != 0)
        throw InputError(
            fmt::format("{}: folder {} does not exist or is not writable", path, folder.string()));
}

void write_volume_mesh(const VolumeMesh& mesh, const std::string& path) {
    check_volume_mesh_output(path);
    const std::string ext = vtk_support::extension(path);
    const std::string temporary = path + ".partial" + ext;
    vtk_support::take_message();
    int status;
    if (ext == ".vtu") {
        vtkNew<vtkXMLUnstructuredGridWriter> writer;
        writer->SetFileName(temporary.c_str());
        writer->SetInputData(to_vtk(mesh));
        vtk_support::configure_xml_writer(*writer);
        status = writer->Write();
    } else {
        vtkNew<vtkUnstructuredGridWriter> writer;
        writer->SetFileName(temporary.c_str());
        writer->SetInputData(to_vtk(mesh));
        writer->SetFileTypeToBinary();
        status = writer->Write();
    }
    std::error_code ec;
    try {
        vtk_support::check_written(status, path);
    } catch (...) {
        fs::remove(temporary, ec);
        throw;
    }
    fs::rename(temporary, path, ec);
    if (ec) {
        fs::remove(temporary, ec);
        throw std::runtime_error(fmt::format("{}: cannot move the written mesh into place", path));
    }
}

}  // namespace hexmesh

#include "io/vtk_mesh.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCompositeDataIterator.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLStructuredGridWriter.h>

#include <filesystem>
#include <fstream>
#include <unordered_map>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/quality/cell_quality.h"
#include "io/export_grid.h"
#include "io/gmsh_mesh.h"
#include "io/input_error.h"
#include "io/legacy_vtk.h"
#include "io/markup.h"
#include "io/medit_mesh.h"
#include "io/plot3d.h"
#include "io/vtk_support.h"
#include "io/xml_vtk.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

// The block as a VTK structured grid with the arrays write_vtk_grid promises. It may point
// into grid.points: write it before `grid` changes or goes.
vtkSmartPointer<vtkStructuredGrid> to_vtk_block(const BlockGrid& grid, const Block& block) {
    auto out = vtkSmartPointer<vtkStructuredGrid>::New();
    out->SetDimensions(block.nodes.ni, block.nodes.nj, block.nodes.nk);
    // Filled in parallel through the arrays' own storage.
    const Id count = block.nodes.count();
    vtkNew<vtkDoubleArray> coordinates;
    coordinates->SetNumberOfComponents(3);
    // A block that is its grid's points in order (one block made at a time) lends them to
    // VTK for the write instead of copying them: `out` does not outlive the call's writer.
    static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
    bool own_points = count > 0 && Id(grid.points.size()) == count;
    for (Id m = 0; own_points && m < count; ++m) own_points = block.node_ids[m] == m;
    if (own_points) {
        coordinates->SetArray(const_cast<double*>(grid.points.data()->data()), 3 * count,
                              /*save: VTK must not free it*/ 1);
    } else {
        coordinates->SetNumberOfTuples(count);
    }
    double* xyz = coordinates->GetPointer(0);
    vtkNew<vtkUnsignedCharArray> kinds;
    kinds->SetName("vertex_kind");
    kinds->SetNumberOfValues(count);
    unsigned char* kind = kinds->GetPointer(0);
    tbb::parallel_for(Id(0), count, [&](Id m) {
        const Id v = block.node_ids[m];
        if (!own_points)
            for (int a = 0; a < 3; ++a) xyz[3 * m + a] = grid.points[v][a];
        kind[m] = grid.kinds.empty() ? 0 : uint8_t(grid.kinds[v]);
    });
    vtkNew<vtkPoints> points;
    points->SetData(coordinates);
    out->SetPoints(points);
    out->GetPointData()->AddArray(kinds);

    vtkNew<vtkDoubleArray> sj;
    sj->SetName("scaled_jacobian");
    sj->SetNumberOfValues(block.cells().count());
    scaled_jacobians(grid, block, sj->GetPointer(0));
    out->GetCellData()->AddArray(sj);

    // Field data keeps what a structured grid cannot say: the block's name and face patches.
    vtkNew<vtkStringArray> name;
    name->SetName("block_name");
    name->InsertNextValue(block.name);
    out->GetFieldData()->AddArray(name);
    vtkNew<vtkStringArray> patches;
    patches->SetName("face_patch");
    for (const std::string& patch : block.face_patch) patches->InsertNextValue(patch);
    out->GetFieldData()->AddArray(patches);
    return out;
}

// Points keyed by their exact coordinates, so copies of one node in several pieces merge.
using PointIds = std::unordered_map<std::array<double, 3>, Id, ArrayHash<double, 3>>;

// Appends the hexahedra of one data set to `mesh`, merging points equal to earlier ones.
void append_hexes(vtkDataSet* data, const std::string& path, HexMesh& mesh, PointIds& point_ids) {
    std::vector<Id> local(data->GetNumberOfPoints());
    for (vtkIdType m = 0; m < data->GetNumberOfPoints(); ++m) {
        std::array<double, 3> x;
        data->GetPoint(m, x.data());
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
            throw InputError(fmt::format("{}: point {} has a non-finite coordinate", path, m));
        auto [it, inserted] = point_ids.emplace(x, mesh.num_points());
        if (inserted) mesh.points.emplace_back(x[0], x[1], x[2]);
        local[m] = it->second;
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
        const int type = data->GetCellType(c);
        if (type != VTK_HEXAHEDRON && type != VTK_VOXEL) {
            throw InputError(
                fmt::format("{}: cell {} has VTK type {}; only hexahedra (12) and "
                            "voxels (11) are supported",
                            path, c, type));
        }
        data->GetCellPoints(c, ids);
        vtk_support::check_cell_points(ids, 8, Id(local.size()), path, c);
        static constexpr int voxel_to_hex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
        for (int v = 0; v < 8; ++v)
            mesh.hexes.push_back(local[ids->GetId(type == VTK_VOXEL ? voxel_to_hex[v] : v)]);
    }
}

// Appends one structured piece to `grid` as a block. Blocks meet only on their faces: points
// on the block's faces are merged with equal points of earlier blocks, interior points are
// the block's own (so the lookup table holds face points only).
void append_block(vtkStructuredGrid* piece, const std::string& fallback_name, BlockGrid& grid,
                  PointIds& point_ids) {
    Block block;
    block.name = fallback_name;
    int dims[3];
    piece->GetDimensions(dims);
    block.nodes = {dims[0], dims[1], dims[2]};
    auto* kinds =
        vtkUnsignedCharArray::SafeDownCast(piece->GetPointData()->GetArray("vertex_kind"));
    block.node_ids.resize(piece->GetNumberOfPoints());
    grid.points.reserve(grid.points.size() + block.node_ids.size());
    grid.kinds.reserve(grid.kinds.size() + block.node_ids.size());
    vtkIdType m = 0;
    for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i, ++m) {
                std::array<double, 3> x;
                piece->GetPoint(m, x.data());
                const bool on_face = i == 0 || j == 0 || k == 0 || i == dims[0] - 1 ||
                                     j == dims[1] - 1 || k == dims[2] - 1;
                if (on_face) {
                    auto [it, inserted] = point_ids.emplace(x, Id(grid.points.size()));
                    block.node_ids[m] = it->second;
                    if (!inserted) continue;
                } else {
                    block.node_ids[m] = Id(grid.points.size());
                }
                grid.points.emplace_back(x[0], x[1], x[2]);
                grid.kinds.push_back(kinds ? VertexKind(kinds->GetValue(m)) : VertexKind{});
            }
    vtkFieldData* fields = piece->GetFieldData();
    if (auto* name = vtkStringArray::SafeDownCast(fields->GetAbstractArray("block_name")))
        if (name->GetNumberOfValues() == 1) block.name = name->GetValue(0);
    if (auto* patches = vtkStringArray::SafeDownCast(fields->GetAbstractArray("face_patch")))
        if (patches->GetNumberOfValues() == 6)
            for (int f = 0; f < 6; ++f) block.face_patch[f] = patches->GetValue(f);
    grid.blocks.push_back(std::move(block));
}

}  // namespace

VtkGridWriter::VtkGridWriter(std::string path, size_t num_blocks)
    : path_(std::move(path)), num_blocks_(num_blocks) {
    const std::string ext = vtk_support::extension(path_);
    if (num_blocks_ == 1 && ext == ".vts") return;
    if (ext != ".vtm")
        throw std::runtime_error(
            fmt::format("{}: a grid of {} blocks is written as .vtm", path_, num_blocks_));
    const fs::path vtm(path_);
    pieces_ = vtm.stem().string();
    std::error_code ec;
    fs::create_directories(vtm.parent_path() / pieces_, ec);
    if (ec)
        throw std::runtime_error(
            fmt::format("{}: cannot create the folder of its blocks ({})", path_, ec.message()));
}

void VtkGridWriter::add(const BlockGrid& grid, const Block& block) {
    if (names_.size() >= num_blocks_)
        throw std::logic_error(
            fmt::format("{}: more blocks than the {} announced", path_, num_blocks_));
    add_piece(names_.size(), grid, block);
    names_.push_back(block.name);
}

void VtkGridWriter::add_piece(size_t index, const BlockGrid& grid, const Block& block) const {
    if (index >= num_blocks_)
        throw std::logic_error(
            fmt::format("{}: block {} of the {} announced", path_, index, num_blocks_));
    // .vtm: the pieces where VTK's multiblock writer puts them, STEM/STEM_<index>.vts.
    const std::string file =
        pieces_.empty()
            ? path_
            : (fs::path(path_).parent_path() / pieces_ / fmt::format("{}_{}.vts", pieces_, index))
                  .string();
    vtk_support::take_message();
    vtkNew<vtkXMLStructuredGridWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputData(to_vtk_block(grid, block));
    vtk_support::configure_xml_writer(*writer);
    vtk_support::check_written(writer->Write(), file);
}

void VtkGridWriter::finish() {
    if (names_.size() != num_blocks_)
        throw std::logic_error(fmt::format("{}: {} blocks written of the {} announced", path_,
                                           names_.size(), num_blocks_));
    write_index(names_);
}

void VtkGridWriter::write_index(const std::vector<std::string>& names) const {
    if (pieces_.empty()) return;
    // The index VTK's XML multiblock reader reads: one DataSet per block, named.
    std::string xml =
        "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" "
        "header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n";
    for (size_t b = 0; b < names.size(); ++b)
        xml +=
            fmt::format("    <DataSet index=\"{}\" name=\"{}\" file=\"{}/{}_{}.vts\"/>\n", b,
                        escape_markup(names[b]), escape_markup(pieces_), escape_markup(pieces_), b);
    xml += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    std::ofstream out(path_, std::ios::binary);
    out << xml;
    out.close();
    if (!out) throw std::runtime_error(fmt::format("{}: cannot write the file", path_));
}

void write_vtk_grid(const BlockGrid& grid, const std::string& path) {
    VtkGridWriter writer(path, grid.blocks.size());
    for (const Block& block : grid.blocks) writer.add(grid, block);
    writer.finish();
}

HexMesh read_vtk_mesh(const std::string& path) {
    vtk_support::require_file(path);
    const std::string ext = vtk_support::extension(path);
    vtkSmartPointer<vtkDataObject> data;
    if (ext == ".vts" || ext == ".vtu" || ext == ".vtm")
        data = read_xml_vtk(path);
    else if (ext == ".vtk")
        data = read_legacy_vtk(path);
    else if (ext == ".msh")
        return read_gmsh_mesh(path);
    else if (ext == ".mesh")
        return read_medit_mesh(path);
    else if (is_plot3d_path(path))
        return to_hex_mesh(read_plot3d(path));
    else
        throw InputError(
            fmt::format("{}: unknown mesh format '{}' (expected .vts, .vtu, .vtk, "
                        ".vtm, .msh, .mesh or Plot3D .xyz .x .p3d .g)",
                        path, ext));

    HexMesh mesh;
    PointIds point_ids;
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(data)) {
        vtkSmartPointer<vtkCompositeDataIterator> it;
        it.TakeReference(composite->NewIterator());
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
            if (auto* piece = vtkDataSet::SafeDownCast(it->GetCurrentDataObject()))
                append_hexes(piece, path, mesh, point_ids);
    } else if (auto* single = vtkDataSet::SafeDownCast(data)) {
        append_hexes(single, path, mesh, point_ids);
    }
    if (mesh.num_cells() == 0)
        throw InputError(fmt::format("{}: the file holds no hexahedra", path));
    return mesh;
}

BlockGrid read_vtk_block_grid(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such grid file", path));
    const std::string ext = vtk_support::extension(path);
    vtkSmartPointer<vtkDataObject> data;
    if (ext == ".vts" || ext == ".vtm")
        data = read_xml_vtk(path);
    else
        throw InputError(
            fmt::format("{}: a block grid is read from .vts or .vtm, not '{}'", path, ext));

    BlockGrid grid;
    PointIds point_ids;
    auto add = [&](vtkDataObject* piece, const std::string& name) {
        auto* structured = vtkStructuredGrid::SafeDownCast(piece);
        if (!structured)
            throw InputError(fmt::format("{}: piece '{}' is not a structured grid", path, name));
        append_block(structured, name, grid, point_ids);
    };
    if (auto* composite = vtkCompositeDataSet::SafeDownCast(data)) {
        vtkSmartPointer<vtkCompositeDataIterator> it;
        it.TakeReference(composite->NewIterator());
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
            std::string name = fmt::format("block{}", grid.blocks.size());
            if (it->HasCurrentMetaData() &&
                it->GetCurrentMetaData()->Has(vtkCompositeDataSet::NAME()))
                name = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
            add(it->GetCurrentDataObject(), name);
        }
    } else {
        add(data, fs::path(path).stem().string());
    }
    if (grid.blocks.empty()) throw InputError(fmt::format("{}: the file holds no blocks", path));
    return grid;
}

}  // namespace hexmesh

// The data sets of a VTK XML file: a StructuredGrid of one piece (its extents checked), an
// UnstructuredGrid of one piece (its cell list checked: types, offsets, ids among the points), a
// vtkMultiBlockDataSet of .vts and .vtu pieces; each with its points and point, cell and field
// data.
#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStructuredGrid.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <type_traits>

#include "io/vtk_support.h"
#include "io/xml_vtk_file.h"

namespace hexmesh::xml {
namespace {

namespace fs = std::filesystem;

// Copies integer values to 64-bit ones; the index of the first that does not fit, or -1.
template <class T>
long long widen(const T* values, std::vector<vtkTypeInt64>& out) {
    for (size_t k = 0; k < out.size(); ++k) {
        if constexpr (std::is_unsigned_v<T> && sizeof(T) == 8)
            if (values[k] > T(std::numeric_limits<vtkTypeInt64>::max())) return (long long)k;
        out[k] = vtkTypeInt64(values[k]);
    }
    return -1;
}

}  // namespace

// The only array of a <Points> or similar section.
const Element& XmlVtkFile::only_array(const Element& section) {
    if (section.children.size() != 1 || section.children[0].name != "DataArray")
        fail(fmt::format("<{}> holds {} elements; expected one <DataArray>", section.name,
                         section.children.size()));
    return section.children[0];
}

// The piece's <Points>: `points` points of 3 components, finite.
vtkSmartPointer<vtkPoints> XmlVtkFile::read_points(const Element& piece, long long points) {
    const Element* section = piece.child("Points");
    if (!section) {
        if (points == 0) return vtkSmartPointer<vtkPoints>::New();
        fail("its piece has no <Points>");
    }
    if (points == 0 && section->children.empty())
        return vtkSmartPointer<vtkPoints>::New();  // as VTK writes none
    const Element& array = only_array(*section);
    if (array.value("NumberOfComponents", "1") != "3")
        fail(fmt::format("the points array '{}' has {} components; expected 3",
                         printable(array.value("Name")),
                         printable(array.value("NumberOfComponents", "1"))));
    vtkSmartPointer<vtkAbstractArray> read = read_array(array, points, "the points");
    auto* xyz = vtkDataArray::SafeDownCast(read);
    if (!xyz) fail("its points are strings");
    if (xyz->GetDataType() == VTK_FLOAT || xyz->GetDataType() == VTK_DOUBLE)
        for (vtkIdType m = 0; m < xyz->GetNumberOfTuples(); ++m)
            for (int a = 0; a < 3; ++a)
                if (!std::isfinite(xyz->GetComponent(m, a)))
                    fail(fmt::format("point {} has a non-finite coordinate", m));
    auto out = vtkSmartPointer<vtkPoints>::New();
    out->SetData(xyz);
    return out;
}

// The one <Piece> of a data set element.
const Element& XmlVtkFile::only_piece(const Element& set) {
    std::vector<const Element*> pieces;
    for (const Element& c : set.children)
        if (c.name == "Piece") pieces.push_back(&c);
    if (pieces.size() != 1)
        fail(fmt::format("its <{}> holds {} pieces; this reader reads files of one piece", set.name,
                         pieces.size()));
    return *pieces[0];
}

// The data set element its <VTKFile> holds, <StructuredGrid> or the like.
const Element& XmlVtkFile::data_set(const char* kind) {
    const Element* set = head_.root.child(kind);
    if (!set) fail(fmt::format("a {} file without its <{}> element", kind, kind));
    return *set;
}

// An extent attribute: six integers, three ranges that run forwards within what a grid holds.
std::array<long long, 6> XmlVtkFile::extent(const Element& element, const char* key,
                                            const char* what) {
    const std::string text = element.value(key);
    std::array<long long, 6> e{};
    size_t at = 0;
    for (long long& v : e) {
        while (at < text.size() && is_blank(text[at])) ++at;
        const auto r = std::from_chars(text.data() + at, text.data() + text.size(), v);
        if (r.ec != std::errc())
            fail(fmt::format("{} \"{}\": expected six integers", what, printable(text)));
        at = size_t(r.ptr - text.data());
    }
    if (text.find_first_not_of(" \t\r\n", at) != std::string::npos)
        fail(fmt::format("{} \"{}\": expected six integers", what, printable(text)));
    for (int a = 0; a < 3; ++a) {
        if (e[2 * a] > e[2 * a + 1])
            fail(fmt::format("{} \"{}\": a range runs backwards", what, printable(text)));
        if (e[2 * a] < -(1LL << 40) || e[2 * a + 1] > (1LL << 40) ||
            e[2 * a + 1] - e[2 * a] >= std::numeric_limits<int>::max())
            fail(fmt::format("{} \"{}\": a range beyond what a grid holds", what, printable(text)));
    }
    return e;
}

vtkSmartPointer<vtkDataObject> XmlVtkFile::structured_grid() {
    const Element& set = data_set("StructuredGrid");
    const std::array<long long, 6> whole = extent(set, "WholeExtent", "WholeExtent");
    const Element& piece = only_piece(set);
    const std::array<long long, 6> e = extent(piece, "Extent", "Piece Extent");
    for (int a = 0; a < 3; ++a)
        if (e[2 * a] < whole[2 * a] || e[2 * a + 1] > whole[2 * a + 1])
            fail(
                fmt::format("a Piece Extent reaches outside the WholeExtent on axis {}", "xyz"[a]));
    std::array<int, 3> dims{};
    long long points = 1, cells = 1;
    for (int a = 0; a < 3; ++a) {
        dims[size_t(a)] = int(e[2 * a + 1] - e[2 * a] + 1);
        if (points > std::numeric_limits<long long>::max() / 4 / dims[size_t(a)])
            fail("its Piece Extent makes more points than a grid holds");
        points *= dims[size_t(a)];
        cells *= std::max(1, dims[size_t(a)] - 1);
    }
    auto grid = vtkSmartPointer<vtkStructuredGrid>::New();
    vtkSmartPointer<vtkPoints> xyz = read_points(piece, points);
    grid->SetDimensions(dims.data());
    grid->SetPoints(xyz);
    read_arrays(piece.child("PointData"), points, grid->GetPointData(), "the point data");
    read_arrays(piece.child("CellData"), cells, grid->GetCellData(), "the cell data");
    read_arrays(set.child("FieldData"), -1, grid->GetFieldData(), "the field data");
    return grid;
}

// An integer array of a cell list, as 64-bit values.
std::vector<vtkTypeInt64> XmlVtkFile::integers(const Element& section, const char* name,
                                               long long count) {
    const Element* found = nullptr;
    for (const Element& c : section.children) {
        if (c.name != "DataArray")
            fail(fmt::format("<Cells> holds a <{}> element; expected arrays only", c.name));
        if (c.value("Name") == name) found = &c;
        if (c.value("Name") == "faces" || c.value("Name") == "faceoffsets")
            fail("its <Cells> hold polyhedra (faces, faceoffsets), which are not read");
    }
    if (!found) fail(fmt::format("its <Cells> have no '{}' array", name));
    vtkSmartPointer<vtkAbstractArray> read = read_array(*found, count, "the cells");
    const std::optional<ValueType> type = value_type(found->value("type"));
    auto* values = vtkDataArray::SafeDownCast(read);
    if (!values || !type->integer)
        fail(fmt::format("the cells' '{}' array has type {}; expected an integer type", name,
                         found->value("type")));
    charge(8.0 * double(values->GetNumberOfValues()), fmt::format("the cells' '{}' array", name));
    std::vector<vtkTypeInt64> out(size_t(values->GetNumberOfValues()));
    long long too_large = -1;
    switch (values->GetDataType()) {
        vtkTemplateMacro(too_large =
                             widen(static_cast<const VTK_TT*>(values->GetVoidPointer(0)), out));
        default:
            break;
    }
    if (too_large >= 0)
        fail(fmt::format("the cells' '{}' value {} is beyond 64-bit ids", name, too_large));
    return out;
}

// The <Cells> of a piece of `cells` cells and `points` points, set on `grid` once each type is
// one VTK knows (no polyhedron), the offsets run forwards to the end of the connectivity and
// every id lies among the points.
void XmlVtkFile::read_cells(const Element& section, long long cells, long long points,
                            vtkUnstructuredGrid* grid) {
    const std::vector<vtkTypeInt64> types = integers(section, "types", cells);
    const std::vector<vtkTypeInt64> ends = integers(section, "offsets", cells);
    const std::vector<vtkTypeInt64> ids = integers(section, "connectivity", -1);
    charge(9.0 * double(cells) + 8.0 * double(ids.size()), "the cell list");
    vtkNew<vtkUnsignedCharArray> cell_types;
    cell_types->SetNumberOfValues(cells);
    vtkNew<vtkTypeInt64Array> offsets, connectivity;
    offsets->SetNumberOfValues(cells + 1);
    offsets->SetValue(0, 0);
    for (long long c = 0; c < cells; ++c) {
        const vtkTypeInt64 type = types[size_t(c)];
        if (type < 0 || type > 255 ||
            std::strcmp(vtkCellTypes::GetClassNameFromTypeId(int(type)), "UnknownClass") == 0)
            fail(fmt::format("cell {} has type {}, which VTK does not know", c, type));
        if (type == VTK_POLYHEDRON)
            fail(fmt::format("cell {} is a polyhedron (42), which is not read", c));
        cell_types->SetValue(c, static_cast<unsigned char>(type));
        const vtkTypeInt64 from = offsets->GetValue(c), to = ends[size_t(c)];
        if (to < from || to > vtkTypeInt64(ids.size()))
            fail(
                fmt::format("the cells' offsets: cell {} ends at {}, after {} and within "
                            "the {} ids of the "
                            "connectivity expected",
                            c, to, from, ids.size()));
        offsets->SetValue(c + 1, to);
    }
    if (offsets->GetValue(cells) != vtkTypeInt64(ids.size()))
        fail(fmt::format("the cells' offsets end at {}; the connectivity holds {} ids",
                         offsets->GetValue(cells), ids.size()));
    connectivity->SetNumberOfValues(vtkIdType(ids.size()));
    for (long long c = 0; c < cells; ++c)
        for (vtkTypeInt64 k = offsets->GetValue(c); k < offsets->GetValue(c + 1); ++k) {
            if (ids[size_t(k)] < 0 || ids[size_t(k)] >= points)
                fail(fmt::format(
                    "cell {} refers to point {}, but the file has {}", c, ids[size_t(k)],
                    points == 0 ? "no points" : fmt::format("points 0 to {}", points - 1)));
            connectivity->SetValue(k, ids[size_t(k)]);
        }
    vtkNew<vtkCellArray> list;
    list->SetData(offsets, connectivity);
    grid->SetCells(cell_types, list);
}

vtkSmartPointer<vtkDataObject> XmlVtkFile::unstructured_grid() {
    const Element& set = data_set("UnstructuredGrid");
    const Element& piece = only_piece(set);
    const auto number = [&](const char* key) {
        const std::string text = piece.value(key);
        const std::optional<unsigned long long> n = count_of(text);
        if (!n || *n > (1ULL << 48)) fail(fmt::format("its Piece has {} \"{}\"", key, text));
        return (long long)*n;
    };
    const long long points = number("NumberOfPoints"), cells = number("NumberOfCells");
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->SetPoints(read_points(piece, points));
    const Element* section = piece.child("Cells");
    if (!section && cells > 0) fail(fmt::format("its piece has {} cells but no <Cells>", cells));
    if (section &&
        !(cells == 0 && section->children.empty()))  // VTK writes an empty grid's <Cells> empty
        read_cells(*section, cells, points, grid);
    read_arrays(piece.child("PointData"), points, grid->GetPointData(), "the point data");
    read_arrays(piece.child("CellData"), cells, grid->GetCellData(), "the cell data");
    read_arrays(set.child("FieldData"), -1, grid->GetFieldData(), "the field data");
    return grid;
}

// Its pieces, each a .vts or .vtu file named by a <DataSet file="..."> (relative to this file's
// folder), in file order.
vtkSmartPointer<vtkDataObject> XmlVtkFile::multiblock() {
    const Element& set = data_set("vtkMultiBlockDataSet");
    auto out = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    const fs::path folder = fs::path(path_).parent_path();
    std::vector<const Element*> found;
    // Depth first, in file order.
    const auto visit = [&](const Element& e, auto& self) -> void {
        for (const Element& c : e.children) {
            if (c.name == "DataSet")
                found.push_back(&c);
            else
                self(c, self);
        }
    };
    visit(set, visit);
    for (const Element* piece : found) {
        const std::string file = piece->value("file");
        if (file.empty()) continue;  // an empty block
        const fs::path piece_path = fs::path(file).is_absolute() ? fs::path(file) : folder / file;
        const std::string ext = vtk_support::extension(piece_path.string());
        if (ext != ".vts" && ext != ".vtu")
            fail(fmt::format("its piece '{}' is a '{}' file; expected .vts or .vtu", file, ext));
        std::error_code ec;
        if (!fs::is_regular_file(piece_path, ec))
            fail(fmt::format("its piece '{}' does not exist", file));
        const unsigned index = out->GetNumberOfBlocks();
        out->SetBlock(index, XmlVtkFile(piece_path.string(), budget_, true).read());
        if (const std::string* name = piece->find("name"))
            out->GetMetaData(index)->Set(vtkCompositeDataSet::NAME(), name->c_str());
    }
    return out;
}

}  // namespace hexmesh::xml

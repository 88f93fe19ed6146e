#include "io/legacy_vtk.h"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStructuredGrid.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <optional>
#include <set>
#include <vector>

#include "io/input_error.h"
#include "io/legacy_vtk_tokens.h"

namespace hexmesh {
namespace {

using namespace legacy_vtk;

// A numeric type named by the next word; `what` names the array in the message.
ValueType numeric_type(Parser& f, const std::string& what, bool integers_only) {
    const std::string name = f.word(fmt::format("the type of {}", what));
    const std::optional<ValueType> type = value_type(name);
    if (!type || type->kind == Kind::String || type->kind == Kind::Bit ||
        (integers_only && type->kind == Kind::Real))
        f.fail(fmt::format("{} of type '{}': expected {}", what, name,
                           integers_only ? "an integer type (int, vtktypeint64, ...)"
                                         : "float, double or an integer type"));
    return *type;
}

// What the data set section holds, as read so far.
struct DataSet {
    long long points = -1;  // until POINTS
    vtkNew<vtkDoubleArray> xyz;
    std::array<long long, 3> dims{-1, -1, -1};  // a structured grid's, until DIMENSIONS
    bool has_cells = false, has_types = false;
    vtkNew<vtkTypeInt64Array> offsets, connectivity;  // offsets: one more than the cells
    vtkNew<vtkUnsignedCharArray> types;
    size_t cells_at = 0;                   // where CELLS is, for errors found later
    vtkSmartPointer<vtkDoubleArray> kept;  // the point array asked for
};

void read_points(Parser& f, DataSet& d) {
    d.points = f.count("the number of points");
    const ValueType type = numeric_type(f, "POINTS", false);
    f.start_data();
    const long long values = f.product(d.points, 3, "POINTS");
    f.check_fits(values, type, "POINTS");
    d.xyz->SetNumberOfComponents(3);
    d.xyz->SetNumberOfTuples(d.points);
    double* x = d.xyz->GetPointer(0);
    for (long long m = 0; m < d.points; ++m, x += 3) {
        for (int a = 0; a < 3; ++a) x[a] = f.real(type, "a coordinate");
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
            f.fail(fmt::format("point {} has a non-finite coordinate", m));
    }
}

// CELLS: from version 5 on, OFFSETS (one more than the cells, from 0 up to the declared size)
// then CONNECTIVITY; before, rows "n id ..." of 4-byte ints, `size` values in all.
void read_cells(Parser& f, DataSet& d, bool offsets_layout, const std::string& version) {
    const long long count = f.count("the CELLS count"), size = f.count("the CELLS size");
    if (!offsets_layout) {
        if (f.data_starts_with("OFFSETS"))
            f.fail(fmt::format("CELLS: OFFSETS instead of rows in a file of version {}", version));
        f.start_data();
        f.check_fits(size, int32, "CELLS");
        if (count > size)
            f.fail(fmt::format("CELLS: {} rows cannot fit in the {} values the line declares",
                               count, size));
        d.offsets->SetNumberOfValues(count + 1);
        d.connectivity->SetNumberOfValues(size - count);
        vtkTypeInt64* offset = d.offsets->GetPointer(0);
        vtkTypeInt64* id = d.connectivity->GetPointer(0);
        offset[0] = 0;
        long long used = 0;  // of the declared values, with the counts of the rows still to come
        for (long long r = 0; r < count; ++r) {
            const long long ids = f.integer(int32, "the id count of a CELLS row");
            used += 1;
            if (ids < 0 || ids > size - used - (count - r - 1))
                f.fail(
                    fmt::format("CELLS: row {} has {} ids, beyond the {} values the line declares",
                                r, ids, size));
            for (long long k = 0; k < ids; ++k) *id++ = f.integer(int32, "a point id");
            used += ids;
            offset[r + 1] = offset[r] + ids;
        }
        if (used != size)
            f.fail(fmt::format("CELLS: its {} rows hold {} values, but the line declares {}", count,
                               used, size));
        return;
    }
    const std::string offsets = f.word("OFFSETS");
    if (upper(offsets) != "OFFSETS")
        f.fail(fmt::format("CELLS: '{}' where a file of version {} has OFFSETS", offsets, version));
    ValueType type = numeric_type(f, "OFFSETS", true);
    f.start_data();
    f.check_fits(count, type, "OFFSETS");
    if (count == 0 && size != 0)
        f.fail(fmt::format("CELLS: no offsets for the {} ids the line declares", size));
    d.offsets->SetNumberOfValues(std::max(count, 1LL));
    vtkTypeInt64* offset = d.offsets->GetPointer(0);
    offset[0] = 0;
    for (long long k = 0; k < count; ++k) {
        const long long o = f.integer(type, "an offset");
        const long long previous = k == 0 ? 0 : offset[k - 1];
        if (o < previous || o > size || (k == 0 && o != 0))
            f.fail(fmt::format("CELLS: offset {} is {}, outside [{}, {}]", k, o,
                               k == 0 ? 0 : previous, k == 0 ? 0 : size));
        offset[k] = o;
    }
    const long long last = offset[std::max(count, 1LL) - 1];
    if (last != size)
        f.fail(
            fmt::format("CELLS: the offsets end at {}, but the line declares {} ids", last, size));
    const std::string connectivity = f.word("CONNECTIVITY");
    if (upper(connectivity) != "CONNECTIVITY")
        f.fail(fmt::format("CELLS: '{}' where CONNECTIVITY follows the offsets", connectivity));
    type = numeric_type(f, "CONNECTIVITY", true);
    f.start_data();
    f.check_fits(size, type, "CONNECTIVITY");
    d.connectivity->SetNumberOfValues(size);
    vtkTypeInt64* id = d.connectivity->GetPointer(0);
    for (long long k = 0; k < size; ++k) id[k] = f.integer(type, "a point id");
}

// CELL_TYPES: one 4-byte int a cell, each a type VTK knows (polyhedra, which need a face list
// this reader does not read, refused).
void read_cell_types(Parser& f, DataSet& d) {
    const long long count = f.count("the CELL_TYPES count");
    f.start_data();
    f.check_fits(count, int32, "CELL_TYPES");
    d.types->SetNumberOfValues(count);
    for (long long c = 0; c < count; ++c) {
        const long long type = f.integer(int32, "a cell type");
        if (type < 0 || type > 255 ||
            std::strcmp(vtkCellTypes::GetClassNameFromTypeId(int(type)), "UnknownClass") == 0)
            f.fail(
                fmt::format("CELL_TYPES: cell {} has type {}, which VTK does not know", c, type));
        if (type == VTK_POLYHEDRON)
            f.fail(fmt::format("CELL_TYPES: cell {} is a polyhedron (42), which is not read", c));
        d.types->SetValue(c, static_cast<unsigned char>(type));
    }
}

void read_dimensions(Parser& f, DataSet& d, long long most) {
    for (long long& n : d.dims) {
        n = f.count("a dimension");
        if (n < 1 || n > most)
            f.fail(fmt::format("DIMENSIONS: {} points along an axis; expected 1 to {}", n, most));
    }
}

// One array's values: kept as `d.kept` when it is the first point array of the name asked for,
// else skipped.
void read_array(Parser& f, DataSet& d, const std::string& name, const std::string& type_name,
                long long tuples, long long components, bool keep) {
    const std::optional<ValueType> type = value_type(type_name);
    if (!type)
        f.fail(fmt::format("array '{}' has type '{}', which VTK does not know", name, type_name));
    const std::string what = fmt::format("array '{}'", name);
    f.start_data();
    const long long values = f.product(tuples, components, what);
    if (!keep || d.kept) {
        f.skip(*type, values, what);
        return;
    }
    if (components < 1 || components > INT_MAX)
        f.fail(fmt::format("the point {} has {} components; expected 1 or more", what, components));
    const std::vector<double> read = f.reals(*type, values, "the point " + what);
    d.kept = vtkSmartPointer<vtkDoubleArray>::New();
    d.kept->SetName(name.c_str());
    d.kept->SetNumberOfComponents(int(components));
    d.kept->SetNumberOfTuples(tuples);
    std::copy(read.begin(), read.end(), d.kept->GetPointer(0));
}

// FIELD name count, then count arrays "name components tuples type" and their values. Among
// the point or cell data (`section` "point" or "cell") an array holds `tuples` values; in the
// data set's own field data (`section` "") any number.
void read_field(Parser& f, DataSet& d, const std::string& section, long long tuples,
                const std::string& keep) {
    f.word("the field's name");
    const long long arrays = f.count("the number of arrays of a FIELD");
    for (long long k = 0; k < arrays; ++k) {
        const std::string name = f.word("the name of a FIELD array");
        if (name == "NULL_ARRAY") continue;
        const long long components =
            f.count(fmt::format("the component count of array '{}'", name));
        const long long held = f.count(fmt::format("the tuple count of array '{}'", name));
        if (!section.empty() && held != tuples)
            f.fail(fmt::format("the {} array \"{}\" has {} values for {} {}s", section, name, held,
                               tuples, section));
        read_array(f, d, name, f.word(fmt::format("the type of array '{}'", name)), held,
                   components, section == "point" && name == keep);
    }
}

// The POINT_DATA and CELL_DATA sections, from the first of them to the end of the file.
void read_attributes(Parser& f, DataSet& d, long long cells, const std::string& keep) {
    std::string section;
    long long tuples = 0;
    while (!f.at_end()) {
        const size_t at = f.position();
        const std::string word = f.word("a keyword");
        const std::string key = upper(word);
        if (key == "POINT_DATA" || key == "CELL_DATA") {
            const long long n = f.count("the " + key + " count");
            tuples = key == "POINT_DATA" ? d.points : cells;
            if (n != tuples)
                f.fail(fmt::format("{} {}: the data set has {} {}", key, n, tuples,
                                   key == "POINT_DATA" ? "points" : "cells"));
            section = key;
            continue;
        }
        if (key == "METADATA") {
            f.skip_metadata();
            continue;
        }
        const bool points = section == "POINT_DATA";
        if (key == "FIELD") {
            read_field(f, d, points ? "point" : "cell", tuples, keep);
            continue;
        }
        static const std::set<std::string> arrays = {
            "SCALARS",      "VECTORS",      "NORMALS",
            "TENSORS",      "TENSORS6",     "GLOBAL_IDS",
            "PEDIGREE_IDS", "EDGE_FLAGS",   "TEXTURE_COORDINATES",
            "LOOKUP_TABLE", "COLOR_SCALARS"};
        if (arrays.count(key) == 0)
            f.fail_at(at, fmt::format("unknown keyword '{}' in the {} section", word, section));
        const std::string name = f.word("the name of a " + key);
        long long components = 1;
        std::string type;
        if (key == "SCALARS") {
            type = f.word("the type of SCALARS " + name);
            std::string next = f.word("LOOKUP_TABLE");
            if (upper(next) != "LOOKUP_TABLE") {
                const auto [end, ec] =
                    std::from_chars(next.data(), next.data() + next.size(), components);
                if (ec != std::errc() || end != next.data() + next.size() || components < 1)
                    f.fail(fmt::format(
                        "SCALARS {}: '{}' where the component count or LOOKUP_TABLE was expected",
                        name, next));
                next = f.word("LOOKUP_TABLE");
            }
            if (upper(next) != "LOOKUP_TABLE")
                f.fail(fmt::format("SCALARS {}: '{}' where LOOKUP_TABLE was expected", name, next));
            f.word("the name of the lookup table of SCALARS " + name);
        } else if (key == "VECTORS" || key == "NORMALS" || key == "TENSORS" || key == "TENSORS6") {
            components = key == "TENSORS" ? 9 : key == "TENSORS6" ? 6 : 3;
            type = f.word("the type of " + key + " " + name);
        } else if (key == "TEXTURE_COORDINATES") {
            components = f.count("the dimension of TEXTURE_COORDINATES " + name);
            if (components < 1 || components > 3)
                f.fail(fmt::format("TEXTURE_COORDINATES {}: dimension {}; expected 1, 2 or 3", name,
                                   components));
            type = f.word("the type of TEXTURE_COORDINATES " + name);
        } else if (key == "GLOBAL_IDS" || key == "PEDIGREE_IDS" || key == "EDGE_FLAGS") {
            type = f.word("the type of " + key + " " + name);
        } else {  // LOOKUP_TABLE, COLOR_SCALARS: colours, bytes if binary, else floats
            components = f.count("the size of " + key + " " + name);
            if (key == "LOOKUP_TABLE") components = f.product(components, 4, key + " " + name);
            type = f.binary() ? "unsigned_char" : "float";
        }
        const long long rows = key == "LOOKUP_TABLE" ? 1 : tuples;
        read_array(f, d, name, type, rows, components,
                   points && key != "LOOKUP_TABLE" && name == keep);
    }
}

// The file's version from its first line, "# vtk DataFile Version x.y": major and minor,
// 1.0 to 5.1.
std::array<int, 2> read_version(Parser& f) {
    const std::string first = f.line();
    const std::string prefix = "# vtk DataFile Version";
    if (first.rfind(prefix, 0) != 0)
        f.fail_at(0, "not a legacy VTK file (its first line is not '# vtk DataFile Version x.x')");
    // The version: two numbers, 1.0 to 5.1.
    int major = -1, minor = -1;
    {
        const char* at = first.c_str() + prefix.size();
        const char* end = first.c_str() + first.size();
        while (at < end && is_space(*at)) ++at;
        auto parsed = std::from_chars(at, end, major);
        bool ok = parsed.ec == std::errc() && parsed.ptr < end && *parsed.ptr == '.';
        if (ok) {
            parsed = std::from_chars(parsed.ptr + 1, end, minor);
            ok = parsed.ec == std::errc();
            for (const char* p = parsed.ptr; ok && p < end; ++p) ok = is_space(*p);
        }
        if (!ok)
            f.fail_at(0, fmt::format("'{}': expected a version of two numbers, as '3.0' or '5.1'",
                                     first));
    }
    const std::string version = fmt::format("{}.{}", major, minor);
    if (major < 1 || major > 5 || (major == 5 && minor > 1))
        f.fail_at(0, fmt::format("version {}: this reader knows versions 1.0 to 5.1", version));
    return {major, minor};
}

// The title, ASCII or BINARY (set on `f`) and the DATASET line: the data set's type, upper
// case, UNSTRUCTURED_GRID or STRUCTURED_GRID.
std::string read_dataset_kind(Parser& f) {
    f.line();  // the title
    const std::string encoding = f.word("ASCII or BINARY");
    if (upper(encoding) != "ASCII" && upper(encoding) != "BINARY")
        f.fail(fmt::format("'{}' where ASCII or BINARY was expected", encoding));
    const std::string dataset = f.word("DATASET");
    if (upper(dataset) != "DATASET")
        f.fail(fmt::format("'{}' where DATASET was expected", dataset));
    const std::string kind_word = f.word("the data set's type");
    const std::string kind = upper(kind_word);
    if (kind != "UNSTRUCTURED_GRID" && kind != "STRUCTURED_GRID") {
        for (const char* other : {"POLYDATA", "STRUCTURED_POINTS", "RECTILINEAR_GRID", "FIELD"})
            if (kind == other)
                f.fail(fmt::format(
                    "a {} data set; volume meshes are read from an UNSTRUCTURED_GRID or a "
                    "STRUCTURED_GRID",
                    kind));
        f.fail(fmt::format("unknown dataset '{}'", kind_word));
    }
    f.set_binary(upper(encoding) == "BINARY");
    return kind;
}

// The data set's sections up to its attributes (POINT_DATA or CELL_DATA, left unread).
void read_geometry(Parser& f, DataSet& d, const std::string& kind, int major,
                   const std::string& version) {
    const bool unstructured = kind == "UNSTRUCTURED_GRID";
    while (!f.at_end()) {
        const size_t at = f.position();
        const std::string word = f.word("a keyword");
        const std::string key = upper(word);
        if (key == "POINT_DATA" || key == "CELL_DATA") {
            f.seek(at);
            break;
        }
        const auto once = [&](bool seen) {
            if (seen) f.fail_at(at, fmt::format("a second {} section", key));
        };
        if (key == "FIELD") {
            read_field(f, d, "", 0, "");
        } else if (key == "METADATA") {
            f.skip_metadata();
        } else if (key == "POINTS") {
            once(d.points >= 0);
            read_points(f, d);
        } else if (unstructured && key == "CELLS") {
            once(d.has_cells);
            d.has_cells = true;
            d.cells_at = at;
            read_cells(f, d, major >= 5, version);
        } else if (unstructured && key == "CELL_TYPES") {
            once(d.has_types);
            d.has_types = true;
            read_cell_types(f, d);
        } else if (!unstructured && key == "DIMENSIONS") {
            once(d.dims[0] >= 0);
            read_dimensions(f, d, std::min<long long>(INT_MAX, static_cast<long long>(f.size())));
        } else {
            f.fail_at(at, fmt::format("unknown keyword '{}' in the {} section", word, kind));
        }
    }
}

// The unstructured grid of the sections read, once CELLS and CELL_TYPES agree and every id
// lies among the points; `cells` its cell count.
vtkSmartPointer<vtkDataSet> unstructured_grid(Parser& f, DataSet& d, vtkPoints* points,
                                              long long& cells) {
    if (d.has_cells != d.has_types)
        f.fail(d.has_cells ? "CELLS without CELL_TYPES" : "CELL_TYPES without CELLS");
    if (!d.has_cells) d.offsets->InsertNextValue(0);  // no cells
    cells = d.types->GetNumberOfValues();
    if (d.offsets->GetNumberOfValues() != cells + 1)
        f.fail(fmt::format("CELL_TYPES: {} types for the {} cells of CELLS", cells,
                           d.offsets->GetNumberOfValues() - 1));
    const vtkTypeInt64* offset = d.offsets->GetPointer(0);
    const vtkTypeInt64* ids = d.connectivity->GetPointer(0);
    for (long long c = 0; c < cells; ++c)
        for (vtkTypeInt64 k = offset[c]; k < offset[c + 1]; ++k) {
            const vtkTypeInt64 id = ids[k];
            if (id < 0 || id >= d.points)
                f.fail_at(
                    d.cells_at,
                    fmt::format(
                        "CELLS: cell {} refers to point {}, but the file has {}", c, id,
                        d.points == 0 ? "no points" : fmt::format("points 0 to {}", d.points - 1)));
        }
    vtkNew<vtkCellArray> list;
    list->SetData(d.offsets, d.connectivity);
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    grid->SetPoints(points);
    grid->SetCells(d.types, list);
    return grid;
}

// The structured grid of the sections read, once its DIMENSIONS make its points; `cells` its
// cell count.
vtkSmartPointer<vtkDataSet> structured_grid(Parser& f, const DataSet& d, vtkPoints* points,
                                            long long& cells) {
    if (d.dims[0] < 0) f.fail("the STRUCTURED_GRID has no DIMENSIONS");
    long long product = 1;  // saturating at one more than the points
    for (long long n : d.dims) product = n > d.points / product ? d.points + 1 : product * n;
    if (product != d.points)
        f.fail(fmt::format("DIMENSIONS {} {} {} do not make the {} points of POINTS", d.dims[0],
                           d.dims[1], d.dims[2], d.points));
    cells = 1;
    for (long long n : d.dims) cells *= std::max(n - 1, 1LL);
    auto grid = vtkSmartPointer<vtkStructuredGrid>::New();
    grid->SetDimensions(int(d.dims[0]), int(d.dims[1]), int(d.dims[2]));
    grid->SetPoints(points);
    return grid;
}

}  // namespace

vtkSmartPointer<vtkDataSet> read_legacy_vtk(const std::string& path,
                                            const std::string& point_array) {
    Parser f(path);
    const std::array<int, 2> version = read_version(f);
    const std::string kind = read_dataset_kind(f);
    DataSet d;
    read_geometry(f, d, kind, version[0], fmt::format("{}.{}", version[0], version[1]));
    // The data set's checks that need all of its sections.
    if (d.points < 0) f.fail(fmt::format("the {} has no POINTS", kind));
    vtkNew<vtkPoints> points;
    points->SetData(d.xyz);
    long long cells = 0;
    const vtkSmartPointer<vtkDataSet> out = kind == "UNSTRUCTURED_GRID"
                                                ? unstructured_grid(f, d, points, cells)
                                                : structured_grid(f, d, points, cells);
    read_attributes(f, d, cells, point_array);
    if (d.kept) out->GetPointData()->AddArray(d.kept);
    return out;
}

}  // namespace hexmesh

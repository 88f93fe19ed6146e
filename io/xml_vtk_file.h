// Private to io/: the reading of one VTK XML file (read_xml_vtk, io/xml_vtk.h), its steps in
// four files: the file's head and settings (xml_vtk.cpp), the bytes of binary arrays
// (xml_vtk_binary.cpp), arrays (xml_vtk_arrays.cpp), data sets (xml_vtk_grids.cpp).
#pragma once

#include <vtkAbstractArray.h>
#include <vtkDataCompressor.h>
#include <vtkDataObject.h>
#include <vtkFieldData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/xml_bytes.h"
#include "io/xml_markup.h"

class vtkUnstructuredGrid;

namespace hexmesh::xml {

// How values are stored: VTK's type id and bytes a value (0 for strings).
struct ValueType {
    int vtk;
    int size;
    bool integer;
};

// The type of a `type` attribute (Int8 ... UInt64, Float32, Float64, String), or none.
std::optional<ValueType> value_type(const std::string& name);

// A non-negative integer attribute, exactly (no sign, no trailing text).
std::optional<unsigned long long> count_of(const std::string& text);

// The memory one read may take, shared by a multiblock file's pieces: every array, string list
// and cell list is charged before it is sized.
struct Budget {
    double left = 0;  // bytes
};

// What a <DataArray> (or <Array>) declares, checked: its name (null when it has none), a
// label for messages, its type, components, tuples (-1: any number) and format.
struct ArrayShape {
    const std::string* name = nullptr;
    std::string label;
    ValueType type{};
    unsigned long long components = 1;
    long long tuples = -1;
    std::string format;

    // The value count the array must hold: -1 when not known, -2 when beyond 64-bit counts.
    long long want_values() const;
};

// What one file shares with the reading of all of its arrays.
class XmlVtkFile {
  public:
    // Gives where `bytes` bytes of an array go, once it has checked their count.
    using Allocate = std::function<char*(uint64_t bytes)>;

    // `piece`: a piece of a multiblock file, which must not be one itself.
    XmlVtkFile(const std::string& path, Budget& budget, bool piece = false)
        : path_(path), piece_(piece), budget_(budget) {}

    [[noreturn]] void fail(const std::string& why) const;

    // The file's data set, by the type its <VTKFile> names.
    vtkSmartPointer<vtkDataObject> read();

  private:
    // The head (xml_vtk.cpp).
    void read_head();
    void read_settings();

    // The bytes of binary arrays (xml_vtk_binary.cpp).
    std::unique_ptr<ByteSource> source_of(const Element& array, const std::string& label);
    uint64_t header(ByteSource& from, const std::string& label, const char* what);
    void charge(double bytes, const std::string& what);
    void read_binary(const Element& array, const std::string& label, const Allocate& allocate);
    void read_data(ByteSource& from, const std::string& label, const Allocate& allocate);
    void read_raw(ByteSource& from, const std::string& label, const Allocate& allocate);
    void read_blocks(ByteSource& from, const std::string& label, const Allocate& allocate);
    size_t uncompress(const std::vector<unsigned char>& packed, unsigned char* out,
                      size_t want) const;

    // Arrays (xml_vtk_arrays.cpp).
    template <class T>
    void parse_values(const std::string& text, T* out, const std::string& label);
    ArrayShape shape_of(const Element& array, long long tuples, const std::string& where);
    vtkSmartPointer<vtkAbstractArray> read_strings(const Element& array, const ArrayShape& s);
    vtkSmartPointer<vtkAbstractArray> read_numbers(const Element& array, const ArrayShape& s);
    vtkSmartPointer<vtkAbstractArray> read_array(const Element& array, long long tuples,
                                                 const std::string& where);
    void read_arrays(const Element* section, long long tuples, vtkFieldData* into,
                     const std::string& where);

    // Data sets (xml_vtk_grids.cpp).
    const Element& only_array(const Element& section);
    vtkSmartPointer<vtkPoints> read_points(const Element& piece, long long points);
    const Element& only_piece(const Element& set);
    const Element& data_set(const char* kind);
    std::array<long long, 6> extent(const Element& element, const char* key, const char* what);
    vtkSmartPointer<vtkDataObject> structured_grid();
    std::vector<vtkTypeInt64> integers(const Element& section, const char* name, long long count);
    void read_cells(const Element& section, long long cells, long long points,
                    vtkUnstructuredGrid* grid);
    vtkSmartPointer<vtkDataObject> unstructured_grid();
    vtkSmartPointer<vtkDataObject> multiblock();

    std::string path_;
    bool piece_ = false;
    Budget& budget_;
    std::ifstream in_;
    uint64_t file_size_ = 0, data_end_ = 0;
    Head head_;
    int header_bytes_ = 4;
    bool big_endian_ = false, appended_base64_ = false;
    std::string compressor_;  // "" when uncompressed
    vtkSmartPointer<vtkDataCompressor>
        codec_;  // zlib's or LZ4's (LZMA: liblzma, with a memory limit)
    std::string appended_text_;
    std::map<uint64_t, uint64_t> appended_ranges_;  // [first, end) of each appended array read
};

}  // namespace hexmesh::xml

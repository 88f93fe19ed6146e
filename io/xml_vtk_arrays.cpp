// The arrays of a VTK XML file: a <DataArray>'s declared type, components and tuples checked,
// its values read from ascii words or binary bytes into a VTK array of that type (strings: a
// vtkStringArray), and the arrays of a point, cell or field data section.
#include <fmt/format.h>
#include <vtkDataArray.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <string_view>
#include <type_traits>

#include "io/xml_vtk_file.h"

namespace hexmesh::xml {
namespace {

// The words of an ascii array, each handed to `take`.
template <class Take>
void for_each_word(const std::string& text, Take take) {
    size_t at = 0;
    while (true) {
        while (at < text.size() && is_blank(text[at])) ++at;
        if (at >= text.size()) return;
        size_t end = at;
        while (end < text.size() && !is_blank(text[end])) ++end;
        take(std::string_view(text).substr(at, end - at));
        at = end;
    }
}

}  // namespace

std::optional<ValueType> value_type(const std::string& name) {
    static const std::pair<const char*, ValueType> types[] = {
        {"Int8", {VTK_TYPE_INT8, 1, true}},        {"UInt8", {VTK_TYPE_UINT8, 1, true}},
        {"Int16", {VTK_TYPE_INT16, 2, true}},      {"UInt16", {VTK_TYPE_UINT16, 2, true}},
        {"Int32", {VTK_TYPE_INT32, 4, true}},      {"UInt32", {VTK_TYPE_UINT32, 4, true}},
        {"Int64", {VTK_TYPE_INT64, 8, true}},      {"UInt64", {VTK_TYPE_UINT64, 8, true}},
        {"Float32", {VTK_TYPE_FLOAT32, 4, false}}, {"Float64", {VTK_TYPE_FLOAT64, 8, false}},
        {"String", {VTK_STRING, 0, false}},
    };
    for (const auto& [n, t] : types)
        if (name == n) return t;
    return std::nullopt;
}

std::optional<unsigned long long> count_of(const std::string& text) {
    unsigned long long v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
    return v;
}

long long ArrayShape::want_values() const {
    if (tuples < 0) return -1;
    if (uint64_t(tuples) > uint64_t(std::numeric_limits<long long>::max()) / components) return -2;
    return tuples * (long long)components;
}

// The values of an ascii array of type T, as many as `out` has room for.
template <class T>
void XmlVtkFile::parse_values(const std::string& text, T* out, const std::string& label) {
    uint64_t k = 0;
    for_each_word(text, [&](std::string_view word) {
        T v{};
        const auto r = std::from_chars(word.data(), word.data() + word.size(),
                                       v);  // "nan", "inf", "-inf" too
        if (r.ec != std::errc() || r.ptr != word.data() + word.size())
            fail(fmt::format(
                "{}: value {} is \"{}\", not a {}", label, k, printable(word),
                std::is_floating_point_v<T> ? "number" : "integer in the array's range"));
        out[k++] = v;
    });
}

// What the array declares, checked, for `tuples` tuples (-1: any number; then NumberOfTuples,
// if given, must be what the array holds).
ArrayShape XmlVtkFile::shape_of(const Element& array, long long tuples, const std::string& where) {
    ArrayShape s;
    s.name = array.find("Name");  // VTK keeps unnamed arrays apart
    s.label = fmt::format("array '{}' of {}", printable(s.name ? *s.name : ""), where);
    const std::string& label = s.label;
    const std::string type_name = array.value("type");
    const std::optional<ValueType> type = value_type(type_name);
    if (!type)
        fail(fmt::format(
            "{} has type \"{}\"; expected one of Int8 ... UInt64, Float32, Float64, String", label,
            printable(type_name)));
    s.type = *type;
    const std::string components_text = array.value("NumberOfComponents", "1");
    const std::optional<unsigned long long> components = count_of(components_text);
    if (!components || *components == 0 || *components > 1000000)
        fail(fmt::format("{} has NumberOfComponents \"{}\"", label, printable(components_text)));
    s.components = *components;
    long long declared = -1;
    if (const std::string* t = array.find("NumberOfTuples")) {
        const std::optional<unsigned long long> n = count_of(*t);
        if (!n || *n > uint64_t(std::numeric_limits<long long>::max()))
            fail(fmt::format("{} has NumberOfTuples \"{}\"", label, printable(*t)));
        declared = (long long)*n;
    }
    if (tuples >= 0 && declared >= 0 && declared != tuples)
        fail(fmt::format("{} declares {} tuples; its piece has {}", label, declared, tuples));
    s.tuples = tuples < 0 ? declared : tuples;
    s.format = array.value("format");
    if (s.format != "ascii" && s.format != "binary" && s.format != "appended")
        fail(fmt::format("{} has format \"{}\"; expected ascii, binary or appended", label,
                         printable(s.format)));
    return s;
}

// Zero-terminated strings (ascii: their bytes as numbers), as many as declared: each takes a
// std::string however short, charged before the bytes are read.
vtkSmartPointer<vtkAbstractArray> XmlVtkFile::read_strings(const Element& array,
                                                           const ArrayShape& s) {
    const std::string& label = s.label;
    const long long want = s.want_values();
    if (want == -2)
        fail(fmt::format("string {} declares {} x {} values", label, s.tuples, s.components));
    if (want < 0) fail(fmt::format("string {} does not declare its NumberOfTuples", label));
    const auto room = [&](uint64_t count) {
        if (count < uint64_t(want))
            fail(fmt::format("string {} declares {} x {} values but holds {} bytes", label,
                             s.tuples, s.components, count));
        charge(double(count) + double(want) * sizeof(std::string), label);
    };
    std::string bytes;
    if (s.format == "ascii") {
        uint64_t words = 0;
        for_each_word(array.text, [&](std::string_view) { ++words; });
        room(words);
        for_each_word(array.text, [&](std::string_view word) {
            unsigned v = 0;
            const auto r = std::from_chars(word.data(), word.data() + word.size(), v);
            if (r.ec != std::errc() || r.ptr != word.data() + word.size() || v > 255)
                fail(fmt::format("{}: \"{}\" is not a byte", label, printable(word)));
            bytes += char(v);
        });
    } else {
        read_binary(array, label, [&](uint64_t count) {
            room(count);
            bytes.resize(size_t(count));
            return bytes.data();
        });
    }
    if (!bytes.empty() && bytes.back() != '\0')
        fail(fmt::format("string {} ends inside a string (no terminating zero)", label));
    const uint64_t held = uint64_t(std::count(bytes.begin(), bytes.end(), '\0'));
    if (uint64_t(want) != held)
        fail(fmt::format("string {} declares {} x {} values but holds {}", label, s.tuples,
                         s.components, held));
    auto out = vtkSmartPointer<vtkStringArray>::New();
    if (s.name) out->SetName(s.name->c_str());
    out->SetNumberOfComponents(int(s.components));
    out->SetNumberOfValues(vtkIdType(held));
    size_t from = 0;
    for (vtkIdType k = 0; k < vtkIdType(held); ++k) {
        const size_t zero = bytes.find('\0', from);
        out->SetValue(k, bytes.substr(from, zero - from));
        from = zero + 1;
    }
    return out;
}

// Numbers: ascii words parsed by the array's type, or binary bytes (swapped to this machine's
// order when big-endian), their count checked against the piece's tuples and the memory limit.
vtkSmartPointer<vtkAbstractArray> XmlVtkFile::read_numbers(const Element& array,
                                                           const ArrayShape& s) {
    const std::string& label = s.label;
    const ValueType type = s.type;
    const auto check_count = [&](uint64_t values) {
        const long long want = s.want_values();
        if (want == -2 || (want >= 0 && uint64_t(want) != values) || values % s.components != 0)
            fail(fmt::format(
                "{} holds {} values; expected {} of {} components", label, values,
                want < 0 ? "a whole number of tuples" : fmt::format("{} tuples", s.tuples),
                s.components));
    };
    vtkSmartPointer<vtkDataArray> out;
    out.TakeReference(vtkDataArray::CreateDataArray(type.vtk));
    if (s.name) out->SetName(s.name->c_str());
    out->SetNumberOfComponents(int(s.components));
    const auto allocate = [&](uint64_t values) -> char* {
        check_count(values);
        charge(double(values) * type.size, label);
        out->SetNumberOfTuples(vtkIdType(values / s.components));
        return static_cast<char*>(out->GetVoidPointer(0));
    };
    if (s.format == "ascii") {
        uint64_t words = 0;
        for_each_word(array.text, [&](std::string_view) { ++words; });
        char* to = allocate(words);
        switch (type.vtk) {
            vtkTemplateMacro(parse_values(array.text, reinterpret_cast<VTK_TT*>(to), label));
            default:
                break;
        }
        return out;
    }
    read_binary(array, label, [&](uint64_t bytes) {
        if (bytes % uint64_t(type.size) != 0)
            fail(fmt::format("{} holds {} bytes, not a whole number of {}-byte values", label,
                             bytes, type.size));
        return allocate(bytes / uint64_t(type.size));
    });
    if (big_endian_ && type.size > 1) {
        auto* bytes = static_cast<unsigned char*>(out->GetVoidPointer(0));
        const uint64_t values = uint64_t(out->GetNumberOfValues());
        for (uint64_t v = 0; v < values; ++v)
            std::reverse(bytes + v * uint64_t(type.size), bytes + (v + 1) * uint64_t(type.size));
    }
    return out;
}

// One <DataArray> (or <Array>) with `tuples` tuples (-1: any number; then NumberOfTuples, if
// given, must be what the array holds).
vtkSmartPointer<vtkAbstractArray> XmlVtkFile::read_array(const Element& array, long long tuples,
                                                         const std::string& where) {
    const ArrayShape s = shape_of(array, tuples, where);
    if (s.type.vtk == VTK_STRING) return read_strings(array, s);
    return read_numbers(array, s);
}

// The arrays of a <PointData>, <CellData> or <FieldData> section, each of `tuples` tuples (-1
// for field data: any).
void XmlVtkFile::read_arrays(const Element* section, long long tuples, vtkFieldData* into,
                             const std::string& where) {
    if (!section) return;
    for (const Element& array : section->children) {
        if (array.name != "DataArray" && array.name != "Array")
            fail(fmt::format("<{}> holds a <{}> element; expected arrays only", section->name,
                             array.name));
        into->AddArray(read_array(array, tuples, where));
    }
}

}  // namespace hexmesh::xml

#include "io/xml_vtk.h"

#include <fmt/format.h>
#include <lzma.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkDataCompressor.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkStructuredGrid.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "hexmesh/core/memory_limit.h"
#include "io/input_error.h"
#include "io/vtk_support.h"
#include "io/xml_bytes.h"
#include "io/xml_markup.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;
using namespace xml;

// How far a compressed block may expand (bytes out per byte in, plus a little): zlib's
// deflate at most 1032, LZ4 255; LZMA (xz) reaches about 7000 on constant data.
double most_expansion(const std::string& compressor) {
    if (compressor == "vtkZLibDataCompressor") return 1032;
    if (compressor == "vtkLZ4DataCompressor") return 256;
    return 16384;
}

// How values are stored: VTK's type id and bytes a value (0 for strings).
struct ValueType {
    int vtk;
    int size;
    bool integer;
};

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

// A non-negative integer attribute, exactly (no sign, no trailing text).
std::optional<unsigned long long> count_of(const std::string& text) {
    unsigned long long v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
    return v;
}

// The memory one read may take, shared by a multiblock file's pieces: every array, string list
// and cell list is charged before it is sized.
struct Budget {
    double left = 0;  // bytes
};

// What one file shares with the reading of all of its arrays.
class XmlVtkFile {
  public:
    // `piece`: a piece of a multiblock file, which must not be one itself.
    XmlVtkFile(const std::string& path, Budget& budget, bool piece = false)
        : path_(path), piece_(piece), budget_(budget) {}

    [[noreturn]] void fail(const std::string& why) const {
        throw InputError(fmt::format("{}: {}", path_, why));
    }

    vtkSmartPointer<vtkDataObject> read() {
        vtk_support::require_file(path_);
        read_head();
        const Element& root = head_.root;
        const std::string type = root.value("type");
        if (type != "StructuredGrid" && type != "UnstructuredGrid" &&
            type != "vtkMultiBlockDataSet")
            fail(
                fmt::format("a VTK XML file of type \"{}\"; expected StructuredGrid (.vts), "
                            "UnstructuredGrid (.vtu) "
                            "or vtkMultiBlockDataSet (.vtm)",
                            printable(type)));
        const std::string header_type = root.value("header_type", "UInt32");
        if (header_type != "UInt32" && header_type != "UInt64")
            fail(fmt::format("header_type is \"{}\"; expected UInt32 or UInt64",
                             printable(header_type)));
        header_bytes_ = header_type == "UInt64" ? 8 : 4;
        const std::string byte_order = root.value("byte_order", "LittleEndian");
        if (byte_order != "LittleEndian" && byte_order != "BigEndian")
            fail(fmt::format("byte_order is \"{}\"; expected LittleEndian or BigEndian",
                             printable(byte_order)));
        big_endian_ = byte_order == "BigEndian";
        compressor_ = root.value("compressor");
        if (!compressor_.empty() && compressor_ != "vtkZLibDataCompressor" &&
            compressor_ != "vtkLZ4DataCompressor" && compressor_ != "vtkLZMADataCompressor")
            fail(fmt::format(
                "compressor \"{}\": expected vtkZLibDataCompressor, vtkLZ4DataCompressor or "
                "vtkLZMADataCompressor",
                printable(compressor_)));
        if (compressor_ == "vtkZLibDataCompressor")
            codec_ = vtkSmartPointer<vtkZLibDataCompressor>::New();
        if (compressor_ == "vtkLZ4DataCompressor")
            codec_ = vtkSmartPointer<vtkLZ4DataCompressor>::New();
        if (head_.has_appended) {
            const std::string encoding = head_.appended().value("encoding");
            if (encoding != "raw" && encoding != "base64")
                fail(fmt::format("AppendedData encoding \"{}\": expected raw or base64",
                                 printable(encoding)));
            appended_base64_ = encoding == "base64";
        }
        if (type == "StructuredGrid") return structured_grid();
        if (type == "UnstructuredGrid") return unstructured_grid();
        if (piece_) fail("a piece of a multiblock file that is a multiblock file itself");
        return multiblock();
    }

  private:
    void read_head() {
        in_.open(path_, std::ios::binary);
        if (!in_) fail("cannot open the file");
        std::error_code ec;
        file_size_ = std::filesystem::file_size(path_, ec);
        if (ec) fail(fmt::format("cannot read its size ({})", ec.message()));
        // The XML only: up to the first appended byte (a grid's appended data are hundreds of MB,
        // read array by array where they lie).
        std::string text;
        std::vector<char> chunk(size_t(1) << 20);
        size_t found = std::string::npos, tag_end = std::string::npos;
        while (in_) {
            in_.read(chunk.data(), std::streamsize(chunk.size()));
            const size_t searched = text.size();
            text.append(chunk.data(), size_t(in_.gcount()));
            // Each search goes on from where the last one ended (a tag left open is not
            // searched again from its start with every chunk).
            if (found == std::string::npos)
                found = text.find("<AppendedData", searched > 16 ? searched - 16 : 0);
            if (found == std::string::npos) continue;
            if (tag_end == std::string::npos) tag_end = text.find('>', std::max(found, searched));
            if (tag_end != std::string::npos &&
                text.find_first_not_of(" \t\r\n", std::max(tag_end + 1, searched)) !=
                    std::string::npos)
                break;
        }
        head_ = parse_head(path_, text);
        if (!head_.has_appended) return;
        // The appended data end where </AppendedData> closes them near the end of the file.
        const uint64_t tail_at = file_size_ > 4096 ? file_size_ - 4096 : 0;
        std::string tail(size_t(file_size_ - tail_at), '\0');
        in_.clear();
        in_.seekg(std::streamoff(tail_at));
        in_.read(tail.data(), std::streamsize(tail.size()));
        tail.resize(size_t(in_.gcount()));
        const size_t closing = tail.rfind("</AppendedData>");
        data_end_ = closing == std::string::npos || tail_at + closing < head_.data_start
                        ? file_size_
                        : tail_at + closing;
        if (head_.data_start > data_end_)
            fail("its appended data starts after the end of the file");
    }

    // The bytes of an array stored in binary (inline base64, or appended at its offset).
    std::unique_ptr<ByteSource> source_of(const Element& array, const std::string& label) {
        const std::string format = array.value("format");
        if (format == "binary") return std::make_unique<Base64Source>(array.text);
        if (!head_.has_appended)
            fail(fmt::format("{} is appended, but the file has no <AppendedData>", label));
        const std::string offset_text = array.value("offset");
        const std::optional<unsigned long long> offset = count_of(offset_text);
        const uint64_t size = data_end_ - head_.data_start;
        if (!offset)
            fail(fmt::format("{} has offset \"{}\"; expected a byte offset", label,
                             printable(offset_text)));
        if (*offset > size)
            fail(fmt::format("{} starts at byte {} of the appended data, which has {}", label,
                             *offset, size));
        if (!appended_base64_)
            return std::make_unique<FileSource>(in_, head_.data_start + *offset, data_end_);
        if (appended_text_.empty() && size > 0) {
            charge(double(size), "its base64 appended data");
            appended_text_.resize(size_t(size));
            FileSource(in_, head_.data_start, data_end_).take(size, appended_text_.data());
        }
        return std::make_unique<Base64Source>(
            std::string_view(appended_text_).substr(size_t(*offset)), *offset);
    }

    uint64_t header(ByteSource& from, const std::string& label, const char* what) {
        unsigned char b[8];
        if (!from.take(uint64_t(header_bytes_), reinterpret_cast<char*>(b)))
            fail(fmt::format("{} ends before its {}", label, what));
        uint64_t v = 0;
        for (int k = 0; k < header_bytes_; ++k)
            v |= uint64_t(b[k]) << (8 * (big_endian_ ? header_bytes_ - 1 - k : k));
        return v;
    }

    // Charges `bytes` to the read's memory budget; `what` names what they are for.
    void charge(double bytes, const std::string& what) {
        if (bytes > budget_.left)
            fail(fmt::format("{} would take the read past the memory limit of {:.2f} GB", what,
                             memory_limit() / 1e9));
        budget_.left -= bytes;
    }

    // Reads a binary array's bytes: `allocate(bytes)` checks the count and gives where they go.
    // Appended arrays must not share bytes (one array's data read again as many is a file
    // that asks for more memory than it holds).
    template <class Allocate>
    void read_binary(const Element& array, const std::string& label, Allocate allocate) {
        std::unique_ptr<ByteSource> from = source_of(array, label);
        const bool appended = array.value("format") == "appended";
        const uint64_t first = from->position();
        read_data(*from, label, allocate);
        if (!appended) return;
        const uint64_t end = from->position();
        const auto next = appended_ranges_.lower_bound(first);
        if ((next != appended_ranges_.end() && next->first < end) ||
            (next != appended_ranges_.begin() && std::prev(next)->second > first))
            fail(fmt::format("{} shares its appended bytes with another array", label));
        appended_ranges_.emplace(first, end);
    }

    template <class Allocate>
    void read_data(ByteSource& from, const std::string& label, Allocate allocate) {
        try {
            if (compressor_.empty()) {
                const uint64_t bytes = header(from, label, "byte count");
                if (bytes > from.most_left())
                    fail(fmt::format("{} claims {} bytes; at most {} are left", label, bytes,
                                     from.most_left()));
                if (!from.take(bytes, allocate(bytes)))
                    fail(fmt::format("{} claims {} bytes; the data end first", label, bytes));
                return;
            }
            // [blocks][block size][last block's size, 0 if full][compressed size of each block]
            const uint64_t blocks = header(from, label, "block table");
            const uint64_t block_size = header(from, label, "block table");
            const uint64_t last_size = header(from, label, "block table");
            if (blocks > from.most_left() / uint64_t(header_bytes_))
                fail(fmt::format("{} claims {} compressed blocks; the data end first", label,
                                 blocks));
            if (last_size > block_size || (blocks > 0 && block_size == 0))
                fail(fmt::format("{}: compressed blocks of {} bytes, the last of {}", label,
                                 block_size, last_size));
            std::vector<uint64_t> sizes(static_cast<size_t>(blocks));
            uint64_t compressed = 0;  // saturating
            constexpr uint64_t cap = uint64_t(1) << 62;
            for (uint64_t& s : sizes) {
                s = header(from, label, "block table");
                compressed = std::min(cap, compressed + std::min(s, cap));
            }
            if (compressed > from.most_left())
                fail(fmt::format("{} claims {} compressed bytes; the data end first", label,
                                 compressed));
            uint64_t bytes = 0;
            if (blocks > 0) {
                if (blocks - 1 > (UINT64_MAX - block_size) / block_size)
                    fail(fmt::format("{} claims {} blocks of {} bytes", label, blocks, block_size));
                bytes = (blocks - 1) * block_size + (last_size > 0 ? last_size : block_size);
            }
            // Each block no larger than its compressed bytes can expand to, before anything is
            // sized.
            const auto block_bytes = [&](uint64_t b) {
                return b + 1 == blocks && last_size > 0 ? last_size : block_size;
            };
            const double expansion = most_expansion(compressor_);
            for (uint64_t b = 0; b < blocks; ++b) {
                const uint64_t want = block_bytes(b);
                if (double(want) > expansion * double(sizes[size_t(b)]) + 64)
                    fail(
                        fmt::format("{}: compressed block {} of {} bytes claims {} bytes, more "
                                    "than {} can give",
                                    label, b, sizes[size_t(b)], want, compressor_));
            }
            char* out = allocate(bytes);
            std::vector<unsigned char> packed;
            for (uint64_t b = 0; b < blocks; ++b) {
                packed.resize(size_t(sizes[size_t(b)]));
                if (!from.take(sizes[size_t(b)], reinterpret_cast<char*>(packed.data())))
                    fail(fmt::format("{}: compressed block {} runs past the data", label, b));
                const uint64_t want = block_bytes(b);
                const size_t got = uncompress(
                    packed, reinterpret_cast<unsigned char*>(out + b * block_size), size_t(want));
                if (got != want)
                    fail(fmt::format("{}: compressed block {} does not decompress to its {} bytes",
                                     label, b, want));
            }
        } catch (const DecodeError& e) {
            fail(fmt::format("{}: {}", label, e.why));
        }
    }

    // Decompresses one block into `out` (room for `want` bytes); returns the bytes it gave (0
    // when the block is broken). LZMA is decoded with a memory limit near the block's size (a
    // block's header can ask for a 4 GB dictionary).
    size_t uncompress(const std::vector<unsigned char>& packed, unsigned char* out,
                      size_t want) const {
        if (compressor_ == "vtkLZMADataCompressor") {
            uint64_t limit = uint64_t(want) + (uint64_t(16) << 20);
            size_t in_at = 0, out_at = 0;
            if (lzma_stream_buffer_decode(&limit, 0, nullptr, packed.data(), &in_at, packed.size(),
                                          out, &out_at, want) != LZMA_OK)
                return 0;
            return in_at == packed.size() ? out_at : 0;
        }
        vtk_support::take_message();
        const size_t got = codec_->Uncompress(packed.data(), packed.size(), out, want);
        vtk_support::take_message();
        return got;
    }

    // The words of an ascii array, each handed to `take`.
    template <class Take>
    static void for_each_word(const std::string& text, Take take) {
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

    template <class T>
    void parse_values(const std::string& text, T* out, const std::string& label) {
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

    // One <DataArray> (or <Array>) with `tuples` tuples (-1: any number; then NumberOfTuples, if
    // given, must be what the array holds).
    vtkSmartPointer<vtkAbstractArray> read_array(const Element& array, long long tuples,
                                                 const std::string& where) {
        const std::string* name = array.find("Name");  // VTK keeps unnamed arrays apart
        const std::string label =
            fmt::format("array '{}' of {}", printable(name ? *name : ""), where);
        const std::string type_name = array.value("type");
        const std::optional<ValueType> type = value_type(type_name);
        if (!type)
            fail(fmt::format(
                "{} has type \"{}\"; expected one of Int8 ... UInt64, Float32, Float64, String",
                label, printable(type_name)));
        const std::string components_text = array.value("NumberOfComponents", "1");
        const std::optional<unsigned long long> components = count_of(components_text);
        if (!components || *components == 0 || *components > 1000000)
            fail(
                fmt::format("{} has NumberOfComponents \"{}\"", label, printable(components_text)));
        long long declared = -1;
        if (const std::string* t = array.find("NumberOfTuples")) {
            const std::optional<unsigned long long> n = count_of(*t);
            if (!n || *n > uint64_t(std::numeric_limits<long long>::max()))
                fail(fmt::format("{} has NumberOfTuples \"{}\"", label, printable(*t)));
            declared = (long long)*n;
        }
        if (tuples >= 0 && declared >= 0 && declared != tuples)
            fail(fmt::format("{} declares {} tuples; its piece has {}", label, declared, tuples));
        if (tuples < 0) tuples = declared;
        const std::string format = array.value("format");
        if (format != "ascii" && format != "binary" && format != "appended")
            fail(fmt::format("{} has format \"{}\"; expected ascii, binary or appended", label,
                             printable(format)));
        // The value count the array must hold, when known.
        const auto want_values = [&]() -> long long {
            if (tuples < 0) return -1;
            if (uint64_t(tuples) > uint64_t(std::numeric_limits<long long>::max()) / *components)
                return -2;
            return tuples * (long long)*components;
        };
        const auto check_count = [&](uint64_t values) {
            const long long want = want_values();
            if (want == -2 || (want >= 0 && uint64_t(want) != values) || values % *components != 0)
                fail(fmt::format(
                    "{} holds {} values; expected {} of {} components", label, values,
                    want < 0 ? "a whole number of tuples" : fmt::format("{} tuples", tuples),
                    *components));
        };

        if (type->vtk == VTK_STRING) {
            // Zero-terminated strings (ascii: their bytes as numbers), as many as declared: each
            // takes a std::string however short, charged before the bytes are read.
            const long long want = want_values();
            if (want == -2)
                fail(fmt::format("string {} declares {} x {} values", label, tuples, *components));
            if (want < 0) fail(fmt::format("string {} does not declare its NumberOfTuples", label));
            const auto room = [&](uint64_t count) {
                if (count < uint64_t(want))
                    fail(fmt::format("string {} declares {} x {} values but holds {} bytes", label,
                                     tuples, *components, count));
                charge(double(count) + double(want) * sizeof(std::string), label);
            };
            std::string bytes;
            if (format == "ascii") {
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
                fail(fmt::format("string {} declares {} x {} values but holds {}", label, tuples,
                                 *components, held));
            auto out = vtkSmartPointer<vtkStringArray>::New();
            if (name) out->SetName(name->c_str());
            out->SetNumberOfComponents(int(*components));
            out->SetNumberOfValues(vtkIdType(held));
            size_t from = 0;
            for (vtkIdType k = 0; k < vtkIdType(held); ++k) {
                const size_t zero = bytes.find('\0', from);
                out->SetValue(k, bytes.substr(from, zero - from));
                from = zero + 1;
            }
            return out;
        }

        vtkSmartPointer<vtkDataArray> out;
        out.TakeReference(vtkDataArray::CreateDataArray(type->vtk));
        if (name) out->SetName(name->c_str());
        out->SetNumberOfComponents(int(*components));
        const auto allocate = [&](uint64_t values) -> char* {
            check_count(values);
            charge(double(values) * type->size, label);
            out->SetNumberOfTuples(vtkIdType(values / *components));
            return static_cast<char*>(out->GetVoidPointer(0));
        };
        if (format == "ascii") {
            uint64_t words = 0;
            for_each_word(array.text, [&](std::string_view) { ++words; });
            char* to = allocate(words);
            switch (type->vtk) {
                vtkTemplateMacro(parse_values(array.text, reinterpret_cast<VTK_TT*>(to), label));
                default:
                    break;
            }
            return out;
        }
        read_binary(array, label, [&](uint64_t bytes) {
            if (bytes % uint64_t(type->size) != 0)
                fail(fmt::format("{} holds {} bytes, not a whole number of {}-byte values", label,
                                 bytes, type->size));
            return allocate(bytes / uint64_t(type->size));
        });
        if (big_endian_ && type->size > 1) {
            auto* bytes = static_cast<unsigned char*>(out->GetVoidPointer(0));
            const uint64_t values = uint64_t(out->GetNumberOfValues());
            for (uint64_t v = 0; v < values; ++v)
                std::reverse(bytes + v * uint64_t(type->size),
                             bytes + (v + 1) * uint64_t(type->size));
        }
        return out;
    }

    // The arrays of a <PointData>, <CellData> or <FieldData> section, each of `tuples` tuples (-1
    // for field data: any).
    void read_arrays(const Element* section, long long tuples, vtkFieldData* into,
                     const std::string& where) {
        if (!section) return;
        for (const Element& array : section->children) {
            if (array.name != "DataArray" && array.name != "Array")
                fail(fmt::format("<{}> holds a <{}> element; expected arrays only", section->name,
                                 array.name));
            into->AddArray(read_array(array, tuples, where));
        }
    }

    // The only array of a <Points> or similar section.
    const Element& only_array(const Element& section) {
        if (section.children.size() != 1 || section.children[0].name != "DataArray")
            fail(fmt::format("<{}> holds {} elements; expected one <DataArray>", section.name,
                             section.children.size()));
        return section.children[0];
    }

    vtkSmartPointer<vtkPoints> read_points(const Element& piece, long long points) {
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
    const Element& only_piece(const Element& set) {
        std::vector<const Element*> pieces;
        for (const Element& c : set.children)
            if (c.name == "Piece") pieces.push_back(&c);
        if (pieces.size() != 1)
            fail(fmt::format("its <{}> holds {} pieces; this reader reads files of one piece",
                             set.name, pieces.size()));
        return *pieces[0];
    }

    const Element& data_set(const char* kind) {
        const Element* set = head_.root.child(kind);
        if (!set) fail(fmt::format("a {} file without its <{}> element", kind, kind));
        return *set;
    }

    std::array<long long, 6> extent(const Element& element, const char* key, const char* what) {
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
                fail(fmt::format("{} \"{}\": a range beyond what a grid holds", what,
                                 printable(text)));
        }
        return e;
    }

    vtkSmartPointer<vtkDataObject> structured_grid() {
        const Element& set = data_set("StructuredGrid");
        const std::array<long long, 6> whole = extent(set, "WholeExtent", "WholeExtent");
        const Element& piece = only_piece(set);
        const std::array<long long, 6> e = extent(piece, "Extent", "Piece Extent");
        for (int a = 0; a < 3; ++a)
            if (e[2 * a] < whole[2 * a] || e[2 * a + 1] > whole[2 * a + 1])
                fail(fmt::format("a Piece Extent reaches outside the WholeExtent on axis {}",
                                 "xyz"[a]));
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

    // Copies integer values to 64-bit ones; the index of the first that does not fit, or -1.
    template <class T>
    static long long widen(const T* values, std::vector<vtkTypeInt64>& out) {
        for (size_t k = 0; k < out.size(); ++k) {
            if constexpr (std::is_unsigned_v<T> && sizeof(T) == 8)
                if (values[k] > T(std::numeric_limits<vtkTypeInt64>::max())) return (long long)k;
            out[k] = vtkTypeInt64(values[k]);
        }
        return -1;
    }

    // An integer array of a cell list, as 64-bit values.
    std::vector<vtkTypeInt64> integers(const Element& section, const char* name, long long count) {
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
        charge(8.0 * double(values->GetNumberOfValues()),
               fmt::format("the cells' '{}' array", name));
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

    vtkSmartPointer<vtkDataObject> unstructured_grid() {
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
        if (!section && cells > 0)
            fail(fmt::format("its piece has {} cells but no <Cells>", cells));
        if (section && !(cells == 0 &&
                         section->children.empty())) {  // VTK writes an empty grid's <Cells> empty
            const std::vector<vtkTypeInt64> types = integers(*section, "types", cells);
            const std::vector<vtkTypeInt64> ends = integers(*section, "offsets", cells);
            const std::vector<vtkTypeInt64> ids = integers(*section, "connectivity", -1);
            charge(9.0 * double(cells) + 8.0 * double(ids.size()), "the cell list");
            vtkNew<vtkUnsignedCharArray> cell_types;
            cell_types->SetNumberOfValues(cells);
            vtkNew<vtkTypeInt64Array> offsets, connectivity;
            offsets->SetNumberOfValues(cells + 1);
            offsets->SetValue(0, 0);
            for (long long c = 0; c < cells; ++c) {
                const vtkTypeInt64 type = types[size_t(c)];
                if (type < 0 || type > 255 ||
                    std::strcmp(vtkCellTypes::GetClassNameFromTypeId(int(type)), "UnknownClass") ==
                        0)
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
        read_arrays(piece.child("PointData"), points, grid->GetPointData(), "the point data");
        read_arrays(piece.child("CellData"), cells, grid->GetCellData(), "the cell data");
        read_arrays(set.child("FieldData"), -1, grid->GetFieldData(), "the field data");
        return grid;
    }

    // Its pieces, each a .vts or .vtu file named by a <DataSet file="..."> (relative to this file's
    // folder), in file order.
    vtkSmartPointer<vtkDataObject> multiblock() {
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
            const fs::path piece_path =
                fs::path(file).is_absolute() ? fs::path(file) : folder / file;
            const std::string ext = vtk_support::extension(piece_path.string());
            if (ext != ".vts" && ext != ".vtu")
                fail(
                    fmt::format("its piece '{}' is a '{}' file; expected .vts or .vtu", file, ext));
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

}  // namespace

vtkSmartPointer<vtkDataObject> read_xml_vtk(const std::string& path) {
    Budget budget{memory_limit()};
    return XmlVtkFile(path, budget).read();
}

}  // namespace hexmesh

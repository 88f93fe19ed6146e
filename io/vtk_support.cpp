#include "io/vtk_support.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <cctype>
#include <sstream>
#include <fstream>
#include <fmt/format.h>
#include <stdexcept>
#include <tuple>
#include <vector>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include "io/case_file.h"

namespace hexmesh::vtk_support {
namespace {

// Keeps VTK's first message instead of printing it.
class CapturedMessages : public vtkOutputWindow {
public:
    static CapturedMessages* New();
    vtkTypeMacro(CapturedMessages, vtkOutputWindow)
    void DisplayText(const char* text) override { keep(text); }
    void DisplayErrorText(const char* text) override { keep(text); }
    void DisplayWarningText(const char* text) override { keep(text); }
    void DisplayGenericWarningText(const char* text) override { keep(text); }
    void DisplayDebugText(const char*) override {}

    std::string take() {
        std::string m;
        std::swap(m, first_);
        while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
        const auto nl = m.rfind('\n');
        if (nl != std::string::npos) m = m.substr(nl + 1);
        const auto object = m.find("): ");
        if (object != std::string::npos && m.find(" (0x") < object) m = m.substr(object + 3);
        return m;
    }

private:
    void keep(const char* text) {
        if (first_.empty() && text) first_ = text;
    }
    std::string first_;
};
vtkStandardNewMacro(CapturedMessages)

CapturedMessages& messages() {
    static CapturedMessages* window = [] {
        auto* w = CapturedMessages::New();
        vtkOutputWindow::SetInstance(w);
        vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
        return w;
    }();
    return *window;
}

}  // namespace

std::string take_message() { return messages().take(); }

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext;
}

void check_written(int status, const std::string& path) {
    const std::string why = take_message();
    if (status != 1 || !why.empty())
        throw std::runtime_error(fmt::format("{}: VTK cannot write it: {}", path, why));
}

void configure_xml_writer(vtkXMLWriterBase& writer) {
    writer.SetDataModeToAppended();
    writer.EncodeAppendedDataOff();
    writer.SetCompressorTypeToNone();
    writer.SetHeaderTypeToUInt64();
}

void require_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such mesh file", path));
}

void check_cell_points(vtkIdList* ids, int count, Id points, const std::string& path, vtkIdType cell) {
    if (ids->GetNumberOfIds() < count)
        throw InputError(fmt::format("{}: cell {} has {} point ids where its type takes {}", path, cell,
                                     ids->GetNumberOfIds(), count));
    for (vtkIdType v = 0; v < ids->GetNumberOfIds(); ++v)
        if (ids->GetId(v) < 0 || ids->GetId(v) >= points)
            throw InputError(fmt::format("{}: cell {} refers to point {}, but the file has points 0 to {}",
                                         path, cell, ids->GetId(v), points - 1));
}

void throw_read_error(const std::string& path, const std::string& why) {
    throw InputError(fmt::format("{}: VTK cannot read it: {}", path, why));
}

}  // namespace hexmesh::vtk_support

namespace hexmesh::vtk_support {
namespace {

// The value of attribute `name` in the tag text `tag` ("" when absent).
std::string attribute(const std::string& tag, const std::string& name) {
    for (size_t at = tag.find(name + "=\""); at != std::string::npos; at = tag.find(name + "=\"", at + 1)) {
        if (at > 0 && !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;  // "xoffset" is no "offset"
        const size_t start = at + name.size() + 2, end = tag.find('"', start);
        if (end == std::string::npos) return "";
        return tag.substr(start, end - start);
    }
    return "";
}

// Reads a little- or big-endian unsigned header of `bytes` (4 or 8) at `at`.
std::uint64_t header_value(const std::string& data, size_t at, int bytes, bool big_endian) {
    if (at > data.size() || size_t(bytes) > data.size() - at) return UINT64_MAX;  // short read: no such header
    std::uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) {
        const std::uint64_t byte = static_cast<unsigned char>(data[at + size_t(k)]);
        v |= byte << (8 * (big_endian ? bytes - 1 - k : k));
    }
    return v;
}

}  // namespace

void check_xml_vtk(const std::string& path) {
    require_file(path);
    // The XML head only (up to the first byte of appended data); the appended bytes are read
    // where an array's header or strings lie, not all of them (a grid's are hundreds of MB).
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const size_t file_size = size_t(std::filesystem::file_size(path, ec));
    std::string data;
    {
        std::vector<char> chunk(size_t(1) << 20);
        size_t found = std::string::npos;
        while (in) {
            in.read(chunk.data(), std::streamsize(chunk.size()));
            const size_t searched = data.size();
            data.append(chunk.data(), size_t(in.gcount()));
            if (found == std::string::npos) found = data.find("<AppendedData", searched > 16 ? searched - 16 : 0);
            if (found == std::string::npos) continue;
            const size_t tag_end = data.find('>', found);
            if (tag_end != std::string::npos && data.find_first_not_of(" \t\r\n", tag_end + 1) != std::string::npos) break;
        }
    }
    const auto bytes_at = [&](size_t at, size_t count) {
        std::string bytes(count, '\0');
        in.clear();
        in.seekg(std::streamoff(at));
        in.read(bytes.data(), std::streamsize(count));
        bytes.resize(size_t(in.gcount()));
        return bytes;
    };
    const auto fail = [&](const std::string& why) { throw InputError(fmt::format("{}: {}", path, why)); };
    const size_t appended = data.find("<AppendedData");  // npos: inline data only
    const size_t root = data.find("<VTKFile");
    if (root == std::string::npos) return;  // VTK's reader says what it is not
    const std::string root_tag = data.substr(root, data.find('>', root) - root);
    if (attribute(root_tag, "type") == "vtkMultiBlockDataSet") {
        // Its pieces, each checked as a file of its own.
        const std::filesystem::path folder = std::filesystem::path(path).parent_path();
        for (size_t at = data.find("<DataSet"); at != std::string::npos; at = data.find("<DataSet", at + 1)) {
            const std::string file = attribute(data.substr(at, data.find('>', at) - at), "file");
            if (!file.empty() && std::filesystem::is_regular_file(folder / file)) check_xml_vtk((folder / file).string());
        }
        return;
    }
    const std::string header_type = attribute(root_tag, "header_type");
    if (!header_type.empty() && header_type != "UInt32" && header_type != "UInt64")
        fail(fmt::format("header_type is \"{}\"; expected UInt32 or UInt64", header_type));
    const std::string byte_order = attribute(root_tag, "byte_order");
    if (!byte_order.empty() && byte_order != "LittleEndian" && byte_order != "BigEndian")
        fail(fmt::format("byte_order is \"{}\"; expected LittleEndian or BigEndian", byte_order));
    // Structured pieces: extents of six integers, each range ascending, every piece inside the
    // whole extent (VTK's reader crashed on a piece whose range ran backwards).
    const std::string kind = attribute(root_tag, "type");
    if (kind == "StructuredGrid" || kind == "RectilinearGrid" || kind == "ImageData") {
        const auto extent = [&](const std::string& text, const char* what) {
            std::istringstream in(text);
            std::array<long long, 6> e{};
            for (long long& v : e)
                if (!(in >> v)) fail(fmt::format("{} \"{}\": expected six integers", what, text));
            std::string more;
            if (in >> more) fail(fmt::format("{} \"{}\": expected six integers", what, text));
            for (int a = 0; a < 3; ++a)
                if (e[2 * a] > e[2 * a + 1]) fail(fmt::format("{} \"{}\": a range runs backwards", what, text));
            return e;
        };
        const size_t set = data.find("<" + kind);
        if (set == std::string::npos) fail(fmt::format("a {} file without its <{}> element", kind, kind));
        const std::array<long long, 6> whole =
            extent(attribute(data.substr(set, data.find('>', set) - set), "WholeExtent"), "WholeExtent");
        for (size_t at = data.find("<Piece"); at < appended; at = data.find("<Piece", at + 1)) {
            const std::array<long long, 6> piece = extent(attribute(data.substr(at, data.find('>', at) - at), "Extent"), "Piece Extent");
            for (int a = 0; a < 3; ++a)
                if (piece[2 * a] < whole[2 * a] || piece[2 * a + 1] > whole[2 * a + 1])
                    fail(fmt::format("a Piece Extent reaches outside the WholeExtent on axis {}", "xyz"[a]));
        }
    }
    const int header = header_type == "UInt64" ? 8 : 4;
    const bool big = byte_order == "BigEndian";
    const bool compressed = !attribute(root_tag, "compressor").empty();
    const auto value_bytes = [](const std::string& type) -> unsigned long long {
        if (type == "Int8" || type == "UInt8") return 1;
        if (type == "Int16" || type == "UInt16") return 2;
        if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
        if (type == "Int64" || type == "UInt64" || type == "Float64") return 8;
        return 0;  // String, Bit: not sized so
    };
    // The sections of arrays hold arrays only: VTK's reader makes an array of each element in
    // them, and used the one it could not make (a crash).
    for (const char* section : {"FieldData", "PointData", "CellData", "Points", "Cells", "Coordinates"}) {
        const std::string open = std::string("<") + section, close = std::string("</") + section + ">";
        for (size_t at = data.find(open); at < appended; at = data.find(open, at + 1)) {
            const char after = data[at + open.size()];
            if (after != '>' && after != ' ' && after != '/' && !std::isspace(static_cast<unsigned char>(after))) continue;
            const size_t end = std::min(data.find(close, at), appended);
            for (size_t e = data.find('<', at + 1); e < end; e = data.find('<', e + 1))
                if (data.compare(e, 10, "<DataArray") != 0 && data.compare(e, 7, "<Array ") != 0 && data[e + 1] != '/' &&
                    data[e + 1] != '!')
                    fail(fmt::format("<{}> holds a <{}> element; expected arrays only", section,
                                     data.substr(e + 1, std::min<size_t>(data.find_first_of(" />", e + 1), end) - e - 1)));
        }
    }
    for (size_t at = data.find('<'); at < appended; at = data.find('<', at + 1)) {
        if (data.compare(at, 10, "<DataArray") != 0 && data.compare(at, 7, "<Array ") != 0) continue;
        const std::string tag = data.substr(at, data.find('>', at) - at);
        // A type VTK does not know: its reader builds no array and then uses it (a crash).
        const std::string type = attribute(tag, "type");
        if (value_bytes(type) == 0 && type != "String" && type != "Bit")
            fail(fmt::format("array '{}' has type \"{}\"; expected one of Int8 ... UInt64, Float32, Float64, String",
                             attribute(tag, "Name"), attribute(tag, "type")));
    }
    if (appended == std::string::npos) return;
    const std::string appended_tag = data.substr(appended, data.find('>', appended) - appended);
    if (attribute(appended_tag, "encoding") != "raw") return;  // base64: VTK decodes and checks it
    // The data starts after the first '_' with nothing but blanks before it (VTK reads from the
    // first character that is not blank, and crashed on a file with another one there).
    const size_t underscore = data.find_first_not_of(" \t\r\n", appended + appended_tag.size() + 1);
    if (underscore == std::string::npos || data[underscore] != '_')
        fail("its AppendedData does not start with '_' after the tag");
    const size_t start = underscore + 1;
    const size_t tail_at = file_size > 4096 ? file_size - 4096 : 0;
    const size_t in_tail = bytes_at(tail_at, file_size - tail_at).rfind("</AppendedData>");
    const size_t closing = in_tail == std::string::npos ? file_size : tail_at + in_tail;
    if (start > file_size) fail("its appended data starts after the end of the file");
    const size_t size = (closing < start ? file_size : closing) - start;
    // Per piece, its point and cell counts (from its extent or its NumberOfPoints and
    // NumberOfCells), and where its point and cell arrays lie: a point or cell array must hold
    // one value (of its components) for each (VTK copied a short one past its end).
    struct Section {
        size_t begin, end;
        unsigned long long tuples;
        bool points;  // the <Points> coordinates: 3 components
    };
    std::vector<Section> sections;
    for (size_t at = data.find("<Piece"); at < appended; at = data.find("<Piece", at + 1)) {
        const std::string tag = data.substr(at, data.find('>', at) - at);
        const size_t end = std::min(data.find("</Piece>", at), appended);
        unsigned long long points = 0, cells = 0;
        if (!attribute(tag, "Extent").empty()) {
            std::istringstream in(attribute(tag, "Extent"));
            std::array<long long, 6> e{};
            for (long long& v : e) in >> v;
            points = cells = 1;
            for (int a = 0; a < 3; ++a) {
                points *= (unsigned long long)(e[2 * a + 1] - e[2 * a] + 1);
                cells *= (unsigned long long)std::max(1ll, e[2 * a + 1] - e[2 * a]);
            }
        } else {
            points = std::strtoull(attribute(tag, "NumberOfPoints").c_str(), nullptr, 10);
            cells = std::strtoull(attribute(tag, "NumberOfCells").c_str(), nullptr, 10);
        }
        for (const auto& [section, tuples, coordinates] :
             {std::tuple{"PointData", points, false}, std::tuple{"CellData", cells, false}, std::tuple{"Points", points, true}}) {
            const std::string open = std::string("<") + section + ">", open_with = std::string("<") + section + " ";
            size_t from = data.find(open, at);
            if (from >= end) from = data.find(open_with, at);
            if (from < end) sections.push_back({from, std::min(data.find(std::string("</") + section + ">", from), end), tuples, coordinates});
        }
    }
    // Every array stored there: its offset, then its byte count (or, compressed, its block
    // table), then its bytes, all inside the appended data.
    for (size_t at = data.find('<'); at < appended; at = data.find('<', at + 1)) {
        const bool array = data.compare(at, 10, "<DataArray") == 0 || data.compare(at, 7, "<Array ") == 0;
        if (!array) continue;
        const std::string tag = data.substr(at, data.find('>', at) - at);
        if (attribute(tag, "format") != "appended") continue;
        const std::string name = attribute(tag, "Name"), offset_text = attribute(tag, "offset");
        char* end = nullptr;
        const unsigned long long offset = std::strtoull(offset_text.c_str(), &end, 10);
        if (offset_text.empty() || *end || offset_text[0] == '-')
            fail(fmt::format("array '{}' has offset \"{}\"; expected a byte offset", name, offset_text));
        const auto past_end = [&](unsigned long long from, unsigned long long count) {
            return from > size || count > size - from;
        };
        if (!compressed) {
            if (past_end(offset, header))
                fail(fmt::format("array '{}' starts at byte {} of the appended data, which has {}", name, offset, size));
            const std::uint64_t bytes = header_value(bytes_at(start + offset, header), 0, header, big);
            if (past_end(offset + header, bytes))
                fail(fmt::format("array '{}' claims {} bytes at byte {} of the appended data, which has {}", name,
                                 bytes, offset, size));
            const std::string components_text = attribute(tag, "NumberOfComponents");
            const unsigned long long components =
                components_text.empty() ? 1 : std::strtoull(components_text.c_str(), nullptr, 10);
            for (const Section& sec : sections) {
                if (at < sec.begin || at >= sec.end) continue;
                if (sec.points && components != 3)
                    fail(fmt::format("the points array '{}' has {} components; expected 3", name,
                                     components_text.empty() ? "1" : components_text));
                const unsigned long long size_of = value_bytes(attribute(tag, "type"));
                if (size_of > 0 && (components == 0 || sec.tuples > bytes || components > bytes ||
                                    sec.tuples * components * size_of != bytes))
                    fail(fmt::format("array '{}' holds {} bytes; its piece needs {} values of {} components of {} bytes",
                                     name, bytes, sec.tuples, components_text.empty() ? "1" : components_text, size_of));
            }
            if (attribute(tag, "type") == "String") {
                // Exactly as many zero-terminated strings as it declares values.
                const std::string tuples = attribute(tag, "NumberOfTuples");
                const unsigned long long t = std::strtoull(tuples.empty() ? "0" : tuples.c_str(), nullptr, 10);
                const unsigned long long c = std::max(1ull, components);
                // Saturating: a count beyond the bytes cannot be held anyway.
                const unsigned long long declared = t > bytes || c > bytes || t * c > bytes ? bytes + 1 : t * c;
                const std::string strings = bytes_at(start + offset + header, bytes);
                const unsigned long long held = std::count(strings.begin(), strings.end(), '\0');
                if (bytes > 0 && strings.back() != '\0')
                    fail(fmt::format("string array '{}' ends inside a string (no terminating zero)", name));
                if (held != declared)  // fewer: VTK reads past them; more: it stores past its array
                    fail(fmt::format("string array '{}' declares {} x {} values but holds {}", name, tuples,
                                     components_text.empty() ? "1" : components_text, held));
            }
            continue;
        }
        // Compressed: [blocks][block size][last block size][compressed size of each block].
        if (past_end(offset, 3ull * header))
            fail(fmt::format("array '{}' starts at byte {} of the appended data, which has {}", name, offset, size));
        const std::string table_head = bytes_at(start + offset, header);
        const std::uint64_t blocks = header_value(table_head, 0, header, big);
        if (blocks > size / std::uint64_t(header) || past_end(offset + 3ull * header, blocks * header))
            fail(fmt::format("array '{}' claims {} compressed blocks at byte {} of the appended data, which has {}",
                             name, blocks, offset, size));
        std::uint64_t total = 0;
        const std::string table = bytes_at(start + offset + 3 * header, blocks * header);
        for (std::uint64_t b = 0; b < blocks; ++b) {
            total += header_value(table, b * header, header, big);
            if (total > size) break;
        }
        if (past_end(offset + (3 + blocks) * header, total))
            fail(fmt::format("array '{}' claims {} compressed bytes at byte {} of the appended data, which has {}",
                             name, total, offset, size));
    }
}

}  // namespace hexmesh::vtk_support

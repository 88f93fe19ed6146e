// The reading of a VTK XML file from its head: the XML up to the appended data, the settings of
// its <VTKFile> (type, header type, byte order, compressor, appended encoding), then the data
// set it names.
#include "io/xml_vtk.h"

#include <fmt/format.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "hexmesh/core/memory_limit.h"
#include "io/input_error.h"
#include "io/vtk_support.h"
#include "io/xml_vtk_file.h"

namespace hexmesh {
namespace xml {

void XmlVtkFile::fail(const std::string& why) const {
    throw InputError(fmt::format("{}: {}", path_, why));
}

vtkSmartPointer<vtkDataObject> XmlVtkFile::read() {
    vtk_support::require_file(path_);
    read_head();
    const Element& root = head_.root;
    const std::string type = root.value("type");
    if (type != "StructuredGrid" && type != "UnstructuredGrid" && type != "vtkMultiBlockDataSet")
        fail(
            fmt::format("a VTK XML file of type \"{}\"; expected StructuredGrid (.vts), "
                        "UnstructuredGrid (.vtu) "
                        "or vtkMultiBlockDataSet (.vtm)",
                        printable(type)));
    read_settings();
    if (type == "StructuredGrid") return structured_grid();
    if (type == "UnstructuredGrid") return unstructured_grid();
    if (piece_) fail("a piece of a multiblock file that is a multiblock file itself");
    return multiblock();
}

// The XML up to the first appended byte, and where the appended data end.
void XmlVtkFile::read_head() {
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
            text.find_first_not_of(" \t\r\n", std::max(tag_end + 1, searched)) != std::string::npos)
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
    if (head_.data_start > data_end_) fail("its appended data starts after the end of the file");
}

// How its binary data are laid out: header type, byte order, compressor, appended encoding.
void XmlVtkFile::read_settings() {
    const Element& root = head_.root;
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
}

}  // namespace xml

vtkSmartPointer<vtkDataObject> read_xml_vtk(const std::string& path) {
    xml::Budget budget{memory_limit()};
    return xml::XmlVtkFile(path, budget).read();
}

}  // namespace hexmesh

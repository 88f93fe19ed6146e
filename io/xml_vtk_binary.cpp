// The bytes of a VTK XML file's binary arrays: where they lie (inline base64, appended raw or
// base64), their byte count or compressed block table, the blocks decompressed (zlib, LZ4,
// LZMA), each count checked against what is left and the memory limit before it sizes anything.
#include <fmt/format.h>
#include <lzma.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string_view>

#include "hexmesh/core/memory_limit.h"
#include "io/vtk_support.h"
#include "io/xml_vtk_file.h"

namespace hexmesh::xml {
namespace {

// How far a compressed block may expand (bytes out per byte in, plus a little): zlib's
// deflate at most 1032, LZ4 255; LZMA (xz) reaches about 7000 on constant data.
double most_expansion(const std::string& compressor) {
    if (compressor == "vtkZLibDataCompressor") return 1032;
    if (compressor == "vtkLZ4DataCompressor") return 256;
    return 16384;
}

// A compressed array's block table: [blocks][block size][last block's size, 0 if full]
// [compressed size of each block], and the bytes the blocks decompress to.
struct BlockTable {
    uint64_t blocks = 0, block_size = 0, last_size = 0;
    std::vector<uint64_t> sizes;
    uint64_t bytes = 0;

    // The bytes block b decompresses to.
    uint64_t block_bytes(uint64_t b) const {
        return b + 1 == blocks && last_size > 0 ? last_size : block_size;
    }
};

}  // namespace

// The bytes of an array stored in binary (inline base64, or appended at its offset).
std::unique_ptr<ByteSource> XmlVtkFile::source_of(const Element& array, const std::string& label) {
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
        fail(fmt::format("{} starts at byte {} of the appended data, which has {}", label, *offset,
                         size));
    if (!appended_base64_)
        return std::make_unique<FileSource>(in_, head_.data_start + *offset, data_end_);
    if (appended_text_.empty() && size > 0) {
        charge(double(size), "its base64 appended data");
        appended_text_.resize(size_t(size));
        FileSource(in_, head_.data_start, data_end_).take(size, appended_text_.data());
    }
    return std::make_unique<Base64Source>(std::string_view(appended_text_).substr(size_t(*offset)),
                                          *offset);
}

// One integer of the file's header type and byte order; `what` names what it counts.
uint64_t XmlVtkFile::header(ByteSource& from, const std::string& label, const char* what) {
    unsigned char b[8];
    if (!from.take(uint64_t(header_bytes_), reinterpret_cast<char*>(b)))
        fail(fmt::format("{} ends before its {}", label, what));
    uint64_t v = 0;
    for (int k = 0; k < header_bytes_; ++k)
        v |= uint64_t(b[k]) << (8 * (big_endian_ ? header_bytes_ - 1 - k : k));
    return v;
}

// Charges `bytes` to the read's memory budget; `what` names what they are for.
void XmlVtkFile::charge(double bytes, const std::string& what) {
    if (bytes > budget_.left)
        fail(fmt::format("{} would take the read past the memory limit of {:.2f} GB", what,
                         memory_limit() / 1e9));
    budget_.left -= bytes;
}

// Reads a binary array's bytes: `allocate(bytes)` checks the count and gives where they go.
// Appended arrays must not share bytes (one array's data read again as many is a file
// that asks for more memory than it holds).
void XmlVtkFile::read_binary(const Element& array, const std::string& label,
                             const Allocate& allocate) {
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

// The array's bytes, uncompressed or block by block; a fault of the base64 text named.
void XmlVtkFile::read_data(ByteSource& from, const std::string& label, const Allocate& allocate) {
    try {
        if (compressor_.empty())
            read_raw(from, label, allocate);
        else
            read_blocks(from, label, allocate);
    } catch (const DecodeError& e) {
        fail(fmt::format("{}: {}", label, e.why));
    }
}

// Uncompressed: a byte count, then the bytes.
void XmlVtkFile::read_raw(ByteSource& from, const std::string& label, const Allocate& allocate) {
    const uint64_t bytes = header(from, label, "byte count");
    if (bytes > from.most_left())
        fail(
            fmt::format("{} claims {} bytes; at most {} are left", label, bytes, from.most_left()));
    if (!from.take(bytes, allocate(bytes)))
        fail(fmt::format("{} claims {} bytes; the data end first", label, bytes));
}

// Compressed: the block table, checked against the data left and against what each block's
// compressed bytes can expand to before anything is sized, then the blocks decompressed.
void XmlVtkFile::read_blocks(ByteSource& from, const std::string& label, const Allocate& allocate) {
    // [blocks][block size][last block's size, 0 if full][compressed size of each block]
    BlockTable t;
    t.blocks = header(from, label, "block table");
    t.block_size = header(from, label, "block table");
    t.last_size = header(from, label, "block table");
    if (t.blocks > from.most_left() / uint64_t(header_bytes_))
        fail(fmt::format("{} claims {} compressed blocks; the data end first", label, t.blocks));
    if (t.last_size > t.block_size || (t.blocks > 0 && t.block_size == 0))
        fail(fmt::format("{}: compressed blocks of {} bytes, the last of {}", label, t.block_size,
                         t.last_size));
    t.sizes.resize(static_cast<size_t>(t.blocks));
    uint64_t compressed = 0;  // saturating
    constexpr uint64_t cap = uint64_t(1) << 62;
    for (uint64_t& s : t.sizes) {
        s = header(from, label, "block table");
        compressed = std::min(cap, compressed + std::min(s, cap));
    }
    if (compressed > from.most_left())
        fail(fmt::format("{} claims {} compressed bytes; the data end first", label, compressed));
    if (t.blocks > 0) {
        if (t.blocks - 1 > (UINT64_MAX - t.block_size) / t.block_size)
            fail(fmt::format("{} claims {} blocks of {} bytes", label, t.blocks, t.block_size));
        t.bytes = (t.blocks - 1) * t.block_size + (t.last_size > 0 ? t.last_size : t.block_size);
    }
    // Each block no larger than its compressed bytes can expand to, before anything is
    // sized.
    const double expansion = most_expansion(compressor_);
    for (uint64_t b = 0; b < t.blocks; ++b) {
        const uint64_t want = t.block_bytes(b);
        if (double(want) > expansion * double(t.sizes[size_t(b)]) + 64)
            fail(
                fmt::format("{}: compressed block {} of {} bytes claims {} bytes, more "
                            "than {} can give",
                            label, b, t.sizes[size_t(b)], want, compressor_));
    }
    char* out = allocate(t.bytes);
    std::vector<unsigned char> packed;
    for (uint64_t b = 0; b < t.blocks; ++b) {
        packed.resize(size_t(t.sizes[size_t(b)]));
        if (!from.take(t.sizes[size_t(b)], reinterpret_cast<char*>(packed.data())))
            fail(fmt::format("{}: compressed block {} runs past the data", label, b));
        const uint64_t want = t.block_bytes(b);
        const size_t got = uncompress(
            packed, reinterpret_cast<unsigned char*>(out + b * t.block_size), size_t(want));
        if (got != want)
            fail(fmt::format("{}: compressed block {} does not decompress to its {} bytes", label,
                             b, want));
    }
}

// Decompresses one block into `out` (room for `want` bytes); returns the bytes it gave (0
// when the block is broken). LZMA is decoded with a memory limit near the block's size (a
// block's header can ask for a 4 GB dictionary).
size_t XmlVtkFile::uncompress(const std::vector<unsigned char>& packed, unsigned char* out,
                              size_t want) const {
    if (compressor_ == "vtkLZMADataCompressor") {
        uint64_t limit = uint64_t(want) + (uint64_t(16) << 20);
        size_t in_at = 0, out_at = 0;
        if (lzma_stream_buffer_decode(&limit, 0, nullptr, packed.data(), &in_at, packed.size(), out,
                                      &out_at, want) != LZMA_OK)
            return 0;
        return in_at == packed.size() ? out_at : 0;
    }
    vtk_support::take_message();
    const size_t got = codec_->Uncompress(packed.data(), packed.size(), out, want);
    vtk_support::take_message();
    return got;
}

}  // namespace hexmesh::xml

// Private to io/: where a VTK XML array's binary bytes come from, base64 text (inline, or
// encoded appended data) or the raw appended bytes of the file, read with every count checked
// against what is left.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>

#include "io/xml_markup.h"

namespace hexmesh::xml {

// The bytes of one array.
class ByteSource {
  public:
    virtual ~ByteSource() = default;
    // Copies the next `count` bytes to `out`; false when fewer are left.
    virtual bool take(uint64_t count, char* out) = 0;
    // At least as many bytes as are left (checked against before anything is sized).
    virtual uint64_t most_left() const = 0;
    // Where the next byte comes from: a byte of the file, or a character of the text.
    virtual uint64_t position() const = 0;
};

struct DecodeError {
    std::string why;
};

// Base64 text, group by group: a group padded with '=' ends early and the next one starts a
// new run (VTK encodes a compressed array's block table and its blocks as separate runs, an
// uncompressed array's header and values as one).
class Base64Source : public ByteSource {
  public:
    // `base`: where `text` starts in what position() counts in (the appended data).
    explicit Base64Source(std::string_view text, uint64_t base = 0) : text_(text), base_(base) {}

    bool take(uint64_t count, char* out) override {
        while (count > 0) {
            if (pending_at_ == pending_count_ && !next_group()) return false;
            const uint64_t n = std::min<uint64_t>(count, uint64_t(pending_count_ - pending_at_));
            std::memcpy(out, pending_ + pending_at_, size_t(n));
            out += n;
            pending_at_ += int(n);
            count -= n;
        }
        return true;
    }
    uint64_t most_left() const override {
        return (text_.size() - at_) / 4 * 3 + 3 + uint64_t(pending_count_ - pending_at_);
    }
    uint64_t position() const override { return base_ + at_; }

  private:
    static int value_of(char ch) {
        if (ch >= 'A' && ch <= 'Z') return ch - 'A';
        if (ch >= 'a' && ch <= 'z') return ch - 'a' + 26;
        if (ch >= '0' && ch <= '9') return ch - '0' + 52;
        if (ch == '+') return 62;
        if (ch == '/') return 63;
        return -1;
    }

    bool next_group() {
        std::uint32_t bits = 0;
        int n = 0, padding = 0;
        while (n < 4) {
            if (at_ >= text_.size()) {
                if (n == 0) return false;
                throw DecodeError{"its base64 text ends inside a group of four characters"};
            }
            const char ch = text_[at_++];
            if (is_blank(ch)) continue;
            int v = 0;
            if (ch == '=') {
                if (n < 2) throw DecodeError{"its base64 text has '=' where a group starts"};
                ++padding;
            } else {
                v = value_of(ch);
                if (v < 0 || padding > 0)
                    throw DecodeError{fmt::format(
                        "its base64 text holds '{}'",
                        v < 0 ? printable(std::string_view(&ch, 1)) : "a character after '='")};
            }
            bits = (bits << 6) | std::uint32_t(v);
            ++n;
        }
        pending_[0] = char(bits >> 16);
        pending_[1] = char((bits >> 8) & 0xFF);
        pending_[2] = char(bits & 0xFF);
        pending_count_ = 3 - padding;
        pending_at_ = 0;
        return true;
    }

    std::string_view text_;
    uint64_t base_ = 0;
    size_t at_ = 0;
    char pending_[3] = {};
    int pending_count_ = 0, pending_at_ = 0;
};

// Raw appended bytes [at, end) of the open file.
class FileSource : public ByteSource {
  public:
    FileSource(std::ifstream& in, uint64_t at, uint64_t end)
        : in_(in), at_(at), end_(std::max(at, end)) {}

    bool take(uint64_t count, char* out) override {
        if (count > end_ - at_) return false;
        in_.clear();
        in_.seekg(std::streamoff(at_));
        in_.read(out, std::streamsize(count));
        if (uint64_t(in_.gcount()) != count) return false;
        at_ += count;
        return true;
    }
    uint64_t most_left() const override { return end_ - at_; }
    uint64_t position() const override { return at_; }

  private:
    std::ifstream& in_;
    uint64_t at_, end_;
};

}  // namespace hexmesh::xml

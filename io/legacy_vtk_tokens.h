// Private to io/legacy_vtk.cpp: the values of a legacy VTK file, ASCII words or big-endian
// binary, read with every count checked against the bytes left before anything is sized.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_error.h"
#include "io/vtk_support.h"

namespace hexmesh::legacy_vtk {

inline std::string upper(std::string text) {
    for (char& ch : text) ch = char(std::toupper(static_cast<unsigned char>(ch)));
    return text;
}

inline bool is_space(char ch) {
    return std::isspace(static_cast<unsigned char>(ch)) != 0;
}

// How an array's values are stored: in a binary file, `size` big-endian bytes each (bits are
// packed eight to a byte, strings carry a length prefix).
enum class Kind { Signed, Unsigned, Real, Bit, String };
struct ValueType {
    Kind kind;
    int size;
};

// The type names VTK's legacy reader knows (any case); vtkIdType is written as a 4-byte int.
inline std::optional<ValueType> value_type(const std::string& name) {
    static const std::pair<const char*, ValueType> types[] = {
        {"BIT", {Kind::Bit, 0}},
        {"CHAR", {Kind::Signed, 1}},
        {"SIGNED_CHAR", {Kind::Signed, 1}},
        {"UNSIGNED_CHAR", {Kind::Unsigned, 1}},
        {"SHORT", {Kind::Signed, 2}},
        {"UNSIGNED_SHORT", {Kind::Unsigned, 2}},
        {"INT", {Kind::Signed, 4}},
        {"UNSIGNED_INT", {Kind::Unsigned, 4}},
        {"VTKIDTYPE", {Kind::Signed, 4}},
        {"LONG", {Kind::Signed, 8}},
        {"UNSIGNED_LONG", {Kind::Unsigned, 8}},
        {"VTKTYPEINT64", {Kind::Signed, 8}},
        {"VTKTYPEUINT64", {Kind::Unsigned, 8}},
        {"FLOAT", {Kind::Real, 4}},
        {"DOUBLE", {Kind::Real, 8}},
        {"STRING", {Kind::String, 0}},
        {"UTF8_STRING", {Kind::String, 0}},
    };
    const std::string key = upper(name);
    for (const auto& [known, type] : types)
        if (key == known) return type;
    return std::nullopt;
}

inline constexpr ValueType int32{Kind::Signed, 4};  // cell rows and cell types

// The file's bytes and a position in them. ASCII values are whitespace-separated words; binary
// values start on the line after their keyword line. Errors name the line (ASCII) or the byte
// (binary) they are found at.
class Parser {
  public:
    explicit Parser(std::string path) : path_(std::move(path)) {
        vtk_support::require_file(path_);
        std::ifstream in(path_, std::ios::binary | std::ios::ate);
        bytes_.resize(size_t(std::max<std::streamoff>(in.tellg(), 0)));
        in.seekg(0);
        in.read(bytes_.data(), std::streamsize(bytes_.size()));
        if (!in) throw InputError(fmt::format("{}: cannot read the file", path_));
    }

    void set_binary(bool binary) { binary_ = binary; }
    bool binary() const { return binary_; }
    size_t size() const { return bytes_.size(); }
    size_t position() const { return at_; }
    void seek(size_t at) { at_ = at; }

    [[noreturn]] void fail(const std::string& why) const { fail_at(at_, why); }
    [[noreturn]] void fail_at(size_t at, const std::string& why) const {
        if (binary_) throw InputError(fmt::format("{}: byte {}: {}", path_, at, why));
        const auto line = 1 + std::count(bytes_.begin(), bytes_.begin() + std::ptrdiff_t(at), '\n');
        throw InputError(fmt::format("{}:{}: {}", path_, line, why));
    }

    // The rest of the current line, without its end; moves to the next line.
    std::string line() {
        const size_t end = std::min(bytes_.find('\n', at_), bytes_.size());
        std::string text = bytes_.substr(at_, end - at_);
        at_ = std::min(end + 1, bytes_.size());
        if (!text.empty() && text.back() == '\r') text.pop_back();
        return text;
    }
    bool at_end() {
        skip_space();
        return at_ == bytes_.size();
    }
    // The next word; `what` names it when the file ends first.
    std::string word(std::string_view what) {
        skip_space();
        const size_t start = at_;
        while (at_ < bytes_.size() && !is_space(bytes_[at_])) ++at_;
        if (start == at_) fail(fmt::format("the file ends where {} was expected", what));
        return bytes_.substr(start, at_ - start);
    }
    // The next word as a count: a whole number, 0 or more.
    long long count(std::string_view what) {
        const std::string text = word(what);
        long long v = -1;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || end != text.data() + text.size() || v < 0)
            fail(fmt::format("{} is '{}'; expected a whole number, 0 or more", what, text));
        return v;
    }
    // Whether the next word (ASCII) or the next data (binary) starts with `text`.
    bool data_starts_with(const std::string& text) {
        const size_t at = at_;
        if (binary_) {
            const size_t end = bytes_.find('\n', at_);
            at_ = end == std::string::npos ? bytes_.size() : end + 1;
        } else {
            skip_space();
        }
        const bool starts = bytes_.compare(at_, text.size(), text) == 0;
        at_ = at;
        return starts;
    }
    // Binary data starts on the line after its keyword line (as VTK reads it).
    void start_data() {
        if (!binary_) return;
        const size_t end = bytes_.find('\n', at_);
        if (end == std::string::npos) fail("the file ends before the data of this section");
        at_ = end + 1;
    }
    // tuples x components, refused beyond 64 bits (check_fits then compares it with the file).
    long long product(long long tuples, long long components, std::string_view what) const {
        if (components != 0 && tuples > LLONG_MAX / components)
            fail(fmt::format("{}: {} x {} values are more than any file holds", what, tuples,
                             components));
        return tuples * components;
    }
    // Refuses `count` values of `type` that the rest of the file cannot hold: nothing is sized
    // from a count before this.
    void check_fits(long long count, ValueType type, std::string_view what) const {
        const size_t left = bytes_.size() - at_;
        const unsigned long long n = static_cast<unsigned long long>(count);
        bool fits;
        if (!binary_ && type.kind == Kind::String)
            fits = n <= left;  // a line each
        else if (!binary_)
            fits = n <= left / 2 + 1;  // a digit and a separator each
        else if (type.kind == Kind::Bit)
            fits = n / 8 + (n % 8 != 0) <= left;
        else if (type.kind == Kind::String)
            fits = n <= left;  // a length byte at least
        else
            fits = n <= left / unsigned(type.size);
        if (!fits)
            fail(fmt::format("{}: {} values do not fit in the {} bytes left in the file", what,
                             count, left));
    }

    // One value as an integer: refused if it is not one, or beyond 64 bits.
    long long integer(ValueType type, std::string_view what) {
        if (!binary_) {
            const std::string text = word(what);
            long long v = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            if (ec != std::errc() || end != text.data() + text.size())
                fail(fmt::format("{}: '{}' is not an integer", what, text));
            return v;
        }
        if (type.kind == Kind::Real || type.kind == Kind::Bit || type.kind == Kind::String)
            fail(fmt::format("{}: expected an integer type", what));
        std::uint64_t bits = big_endian(type.size, what);
        if (type.kind == Kind::Unsigned) {
            if (bits > std::uint64_t(LLONG_MAX))
                fail(fmt::format("{}: {} is beyond 64-bit ids", what, bits));
            return static_cast<long long>(bits);
        }
        if (type.size < 8 && (bits >> (8 * type.size - 1)) != 0)
            bits |= ~std::uint64_t(0) << (8 * type.size);
        return static_cast<long long>(bits);
    }
    // One value of a numeric type as a double.
    double real(ValueType type, std::string_view what) {
        if (!binary_) {
            const std::string text = word(what);
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (end != text.c_str() + text.size())
                fail(fmt::format("{}: '{}' is not a number", what, text));
            return v;
        }
        if (type.kind != Kind::Real) return double(integer(type, what));
        const std::uint64_t bits = big_endian(type.size, what);
        if (type.size == 4) {
            const auto narrow = std::uint32_t(bits);
            float v;
            std::memcpy(&v, &narrow, 4);
            return v;
        }
        double v;
        std::memcpy(&v, &bits, 8);
        return v;
    }
    // `count` values of a numeric type (bits as 0 and 1) as doubles.
    std::vector<double> reals(ValueType type, long long count, std::string_view what) {
        if (type.kind == Kind::String)
            fail(fmt::format("{} holds strings; expected numbers", what));
        check_fits(count, type, what);
        std::vector<double> values(static_cast<size_t>(count));
        if (binary_ && type.kind == Kind::Bit) {  // most significant bit first, as vtkBitArray
            for (size_t k = 0; k < values.size(); ++k)
                values[k] = (static_cast<unsigned char>(bytes_[at_ + k / 8]) >> (7 - k % 8)) & 1;
            at_ += values.size() / 8 + (values.size() % 8 != 0);
        } else {
            for (double& v : values) v = real(type, what);
        }
        return values;
    }
    // Skips `count` values of `type`.
    void skip(ValueType type, long long count, std::string_view what) {
        check_fits(count, type, what);
        const auto n = static_cast<size_t>(count);
        if (type.kind == Kind::String && !binary_) {  // one string a line, after the keyword line
            line();
            for (size_t k = 0; k < n; ++k) {
                if (at_ == bytes_.size())
                    fail(fmt::format("{}: the file ends after {} of its {} strings", what, k, n));
                line();
            }
        } else if (type.kind == Kind::String) {
            // Each string after its length: in 1, 2, 4 or 8 bytes as the first byte's top two
            // bits say (11, 10, 01, 00), those bits cleared but in the 8-byte form.
            for (size_t k = 0; k < n; ++k) {
                if (at_ == bytes_.size())
                    fail(fmt::format("{}: the file ends after {} of its {} strings", what, k, n));
                const int form = static_cast<unsigned char>(bytes_[at_]) >> 6;
                const int size = form == 3 ? 1 : form == 2 ? 2 : form == 1 ? 4 : 8;
                std::uint64_t length = big_endian(size, what);
                if (size < 8) length &= (std::uint64_t(1) << (8 * size - 2)) - 1;
                if (length > bytes_.size() - at_)
                    fail(fmt::format("{}: string {} of {} bytes runs past the end of the file",
                                     what, k, length));
                at_ += size_t(length);
            }
        } else if (binary_) {
            at_ += type.kind == Kind::Bit ? n / 8 + (n % 8 != 0) : n * size_t(type.size);
        } else {
            for (size_t k = 0; k < n; ++k) word(what);
        }
    }
    // A METADATA block (after its keyword): lines up to an empty one.
    void skip_metadata() {
        line();
        while (at_ < bytes_.size()) {
            const std::string text = line();
            if (text.find_first_not_of(" \t\r") == std::string::npos) return;
        }
    }

  private:
    void skip_space() {
        while (at_ < bytes_.size() && is_space(bytes_[at_])) ++at_;
    }
    std::uint64_t big_endian(int size, std::string_view what) {
        if (bytes_.size() - at_ < size_t(size)) fail(fmt::format("the file ends inside {}", what));
        std::uint64_t v = 0;
        for (int b = 0; b < size; ++b)
            v = (v << 8) | static_cast<unsigned char>(bytes_[at_ + size_t(b)]);
        at_ += size_t(size);
        return v;
    }

    std::string path_, bytes_;
    size_t at_ = 0;
    bool binary_ = false;
};

}  // namespace hexmesh::legacy_vtk

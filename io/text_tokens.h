// Whitespace-separated tokens of a text file, for the mesh readers; errors name file and line.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "io/input_error.h"

namespace hexmesh {

class TextTokens {
  public:
    explicit TextTokens(std::string path) : path_(std::move(path)) {
        std::ifstream in(path_, std::ios::binary);
        if (!in) throw InputError(fmt::format("{}: cannot open ({})", path_, std::strerror(errno)));
        std::ostringstream s;
        s << in.rdbuf();
        text_ = s.str();
        at_ = text_.c_str();
    }

    // The file's length in bytes: what any count it declares must fit in.
    size_t size() const { return text_.size(); }
    bool done() {
        skip();
        return *at_ == '\0';
    }
    std::string word() {
        skip();
        const char* start = at_;
        while (*at_ && !std::isspace(static_cast<unsigned char>(*at_))) ++at_;
        if (start == at_) fail("unexpected end of file");
        return std::string(start, at_);
    }
    long long integer(const char* what) {
        skip();
        char* end = nullptr;
        const long long v = std::strtoll(at_, &end, 10);
        if (end == at_ || (*end && !std::isspace(static_cast<unsigned char>(*end))))
            fail(fmt::format("expected {} (an integer)", what));
        at_ = end;
        return v;
    }
    double real(const char* what) {
        skip();
        char* end = nullptr;
        const double v = std::strtod(at_, &end);
        if (end == at_) fail(fmt::format("expected {} (a number)", what));
        at_ = end;
        return v;
    }
    // Skips the rest of the current line.
    void skip_line() {
        while (*at_ && *at_ != '\n') ++at_;
    }
    [[noreturn]] void fail(const std::string& what) const {
        const long line = 1 + long(std::count(text_.c_str(), at_, '\n'));
        throw InputError(fmt::format("{}:{}: {}", path_, line, what));
    }
    const std::string& path() const { return path_; }

  private:
    void skip() {
        while (*at_ && std::isspace(static_cast<unsigned char>(*at_))) ++at_;
    }
    std::string path_, text_;
    const char* at_ = nullptr;
};

}  // namespace hexmesh

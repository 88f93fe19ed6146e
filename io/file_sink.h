// Buffered output file for the exporters: every write error (full disk, no permission) throws.
#pragma once

#include <fmt/format.h>

#include <cstdio>
#include <string>

namespace hexmesh {

// Writes through a large buffer; ASCII writers format into text() and call flush_if_full().
// Throws std::runtime_error naming the file when it cannot be opened or written, including
// at close(), where a full disk shows up. The destructor closes without checking: call
// close() on the success path.
class FileSink {
  public:
    explicit FileSink(std::string path, bool binary = true);
    ~FileSink();
    FileSink(const FileSink&) = delete;
    FileSink& operator=(const FileSink&) = delete;

    void write(const void* data, size_t bytes);
    template <class T>
    void put(const T& value) {
        write(&value, sizeof(T));
    }
    template <class... Args>
    void print(fmt::format_string<Args...> format, Args&&... args) {
        fmt::format_to(std::back_inserter(text_), format, std::forward<Args>(args)...);
        if (text_.size() > (1u << 20)) flush_text();
    }
    void close();
    const std::string& path() const { return path_; }

  private:
    void flush_text();
    [[noreturn]] void fail(const char* what);

    std::string path_;
    std::FILE* file_ = nullptr;
    fmt::memory_buffer text_;
};

}  // namespace hexmesh

#include "io/file_sink.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hexmesh {

FileSink::FileSink(std::string path, bool binary) : path_(std::move(path)) {
    file_ = std::fopen(path_.c_str(), binary ? "wb" : "w");
    if (!file_) fail("cannot create file");
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

FileSink::~FileSink() {
    if (file_) std::fclose(file_);
}

void FileSink::write(const void* data, size_t bytes) {
    flush_text();
    if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes) fail("cannot write");
}

void FileSink::flush_text() {
    if (text_.size() == 0) return;
    if (std::fwrite(text_.data(), 1, text_.size(), file_) != text_.size()) fail("cannot write");
    text_.clear();
}

void FileSink::close() {
    flush_text();
    std::FILE* f = file_;
    file_ = nullptr;
    const bool flushed = std::fflush(f) == 0;
    const int err = errno;
    if (std::fclose(f) != 0 || !flushed) {
        errno = flushed ? errno : err;
        fail("cannot write");
    }
}

void FileSink::fail(const char* what) {
    throw std::runtime_error(fmt::format("{}: {} ({})", path_, what, std::strerror(errno)));
}

}  // namespace hexmesh

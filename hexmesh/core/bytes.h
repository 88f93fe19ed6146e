// Plain values packed into a byte string and read back in the same order: what the processes
// of one job (one build) send each other.
#pragma once

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "hexmesh/core/histogram.h"
#include "hexmesh/core/types.h"

namespace hexmesh {

// Values whose bytes are the value: trivially copyable ones, and Eigen's fixed-size vectors
// (plain arrays of doubles, though not trivially copyable by the letter).
template <class T>
struct is_plain : std::is_trivially_copyable<T> {};
template <>
struct is_plain<Vec3> : std::true_type {};
template <class T, size_t N>
struct is_plain<std::array<T, N>> : is_plain<T> {};

class ByteWriter {
  public:
    template <class T>
    void put(const T& v) {
        static_assert(is_plain<T>::value, "ByteWriter: plain values only");
        bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    template <class T>
    void put(const std::vector<T>& v) {
        static_assert(is_plain<T>::value, "ByteWriter: vectors of plain values only");
        put(v.size());
        if (!v.empty())
            bytes_.append(reinterpret_cast<const char*>(v.data()), sizeof(T) * v.size());
    }
    void put(const std::string& s) {
        put(s.size());
        bytes_ += s;
    }
    void put(const Histogram& h) {
        put(h.lo), put(h.hi), put(h.counts), put(h.below), put(h.above);
    }
    const std::string& bytes() const { return bytes_; }

  private:
    std::string bytes_;
};

// Reads what a ByteWriter wrote, in its order. Throws std::runtime_error past the end.
class ByteReader {
  public:
    explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
    template <class T>
    void get(T& v) {
        static_assert(is_plain<T>::value, "ByteReader: plain values only");
        std::memcpy(static_cast<void*>(&v), take(sizeof(T)), sizeof(T));
    }
    template <class T>
    void get(std::vector<T>& v) {
        static_assert(is_plain<T>::value, "ByteReader: vectors of plain values only");
        size_t n = 0;
        get(n);
        if (n > (bytes_.size() - at_) / std::max<size_t>(1, sizeof(T))) take(bytes_.size() + 1);
        v.resize(n);
        if (n) std::memcpy(static_cast<void*>(v.data()), take(sizeof(T) * n), sizeof(T) * n);
    }
    void get(std::string& s) {
        size_t n = 0;
        get(n);
        s.assign(take(n), n);
    }
    void get(Histogram& h) { get(h.lo), get(h.hi), get(h.counts), get(h.below), get(h.above); }
    template <class T>
    T next() {
        T v{};
        get(v);
        return v;
    }
    bool done() const { return at_ == bytes_.size(); }

  private:
    const char* take(size_t n) {
        if (n > bytes_.size() - at_)
            throw std::runtime_error("a message between processes ended early");
        const char* p = bytes_.data() + at_;
        at_ += n;
        return p;
    }
    const std::string& bytes_;
    size_t at_ = 0;
};

}  // namespace hexmesh

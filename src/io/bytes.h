// Plain values, vectors of them and strings as bytes and back, in the machine's own layout: for
// what this program writes and reads itself (a checkpoint, a mesh part sent between its MPI
// processes). Every read is checked against the bytes' end.
#pragma once

#include "mesh/error.h"
#include "mesh/trimesh.h"

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vesselmesh::io {

// Values copied as bytes: trivially copyable ones and Eigen's fixed-size vectors (their
// coefficients and nothing else).
template <class T>
constexpr bool kPlainBytes = std::is_trivially_copyable_v<T> || std::is_same_v<T, Vec3>;

class ByteWriter {
 public:
  void bytes(const void* data, size_t n) { text_.append(static_cast<const char*>(data), n); }
  template <typename T>
  void value(const T& v) {
    static_assert(kPlainBytes<T>);
    bytes(&v, sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    static_assert(kPlainBytes<T>);
    value<uint64_t>(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value<uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  const std::string& text() const { return text_; }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
};

class ByteReader {
 public:
  // `cut_short(at, size)` throws the error of a read that would pass the end (at: where it began).
  ByteReader(std::string text, std::function<void(size_t at, size_t size)> cut_short)
      : text_(std::move(text)), cut_short_(std::move(cut_short)) {}
  void bytes(void* data, size_t n) {
    if (n == 0) return;
    if (n > text_.size() - at_) fail();
    std::memcpy(data, text_.data() + at_, n);
    at_ += n;
  }
  template <typename T>
  T value() {
    static_assert(kPlainBytes<T>);
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  template <typename T>
  std::vector<T> vector() {
    static_assert(kPlainBytes<T>);
    const uint64_t n = value<uint64_t>();
    if (n > (text_.size() - at_) / sizeof(T)) fail();
    std::vector<T> v(n);
    if (n) bytes(v.data(), n * sizeof(T));
    return v;
  }
  std::string string() {
    const uint64_t n = value<uint64_t>();
    if (n > text_.size() - at_) fail();
    std::string s(n, '\0');
    if (n) bytes(s.data(), n);
    return s;
  }
  bool done() const { return at_ == text_.size(); }

 private:
  [[noreturn]] void fail() const {
    cut_short_(at_, text_.size());
    throw InternalError("a byte reader's cut_short did not throw");
  }
  std::string text_;
  std::function<void(size_t, size_t)> cut_short_;
  size_t at_ = 0;
};

}  // namespace vesselmesh::io

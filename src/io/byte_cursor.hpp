// Bounds-checked reading of serialized data (bag records, ROS 1 and CDR messages). Every read
// checks the remaining length first; running past the end raises ShortData, which the caller turns
// into an InputError that says what it was reading.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace iilfm::io {

struct ShortData {
  std::size_t offset;  // where the read started
  std::size_t wanted;  // bytes it needed
};

template <typename T>
T byte_swapped(T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

class ByteCursor {
 public:
  ByteCursor(const std::uint8_t* data, std::size_t size, bool big_endian = false)
      : data_(data), size_(size), big_endian_(big_endian) {}

  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return size_ - offset_; }
  const std::uint8_t* here() const { return data_ + offset_; }
  void set_big_endian(bool big) { big_endian_ = big; }

  template <typename T>
  T read() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, data_ + offset_, sizeof(T));
    offset_ += sizeof(T);
    return big_endian_ ? byte_swapped(value) : value;
  }
  std::uint8_t u8() { return read<std::uint8_t>(); }
  std::uint32_t u32() { return read<std::uint32_t>(); }
  std::uint64_t u64() { return read<std::uint64_t>(); }

  // Returns the next n bytes and moves past them.
  const std::uint8_t* take(std::size_t n) {
    need(n);
    const std::uint8_t* at = data_ + offset_;
    offset_ += n;
    return at;
  }
  std::string_view take_text(std::size_t n) { return {reinterpret_cast<const char*>(take(n)), n}; }
  void skip(std::size_t n) { take(n); }
  // CDR: moves to the next multiple of n counted from `origin` (the byte after the encapsulation
  // header).
  void align(std::size_t n, std::size_t origin) {
    const std::size_t misalign = (offset_ - origin) % n;
    if (misalign != 0) skip(n - misalign);
  }

 private:
  void need(std::size_t n) const {
    if (n > size_ - offset_) throw ShortData{offset_, n};
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
  bool big_endian_;
};

}  // namespace iilfm::io

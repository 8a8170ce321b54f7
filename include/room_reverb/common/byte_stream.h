#pragma once
// Fixed-width binary fields in a byte buffer, for the encodings that cross a process or a
// machine (simulation_wire.h). Values are written in the host's byte order, which every
// supported machine shares (x86-64 and AArch64 Debian are little-endian; the encoding
// checks it with a marker, see ByteReader::requireMarker). The reader checks every length
// against what is left, so a truncated or corrupt buffer is an InputError, never a read
// past its end.
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

class ByteWriter {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>, "ByteWriter::put takes numbers");
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void putBool(bool value) { put<std::uint8_t>(value ? 1 : 0); }
  void putString(const std::string& text) {
    put<std::uint64_t>(text.size());
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  // A count followed by the values.
  template <typename T>
  void putArray(const T* values, std::size_t count) {
    static_assert(std::is_arithmetic_v<T>, "ByteWriter::putArray takes numbers");
    put<std::uint64_t>(count);
    const auto* p = reinterpret_cast<const std::uint8_t*>(values);
    bytes_.insert(bytes_.end(), p, p + count * sizeof(T));
  }
  void putBytes(const std::vector<std::uint8_t>& bytes) { putArray(bytes.data(), bytes.size()); }

  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<std::uint8_t> bytes_;
};

class ByteReader {
 public:
  // `what` names the buffer in errors ("simulation job").
  ByteReader(const std::uint8_t* data, std::size_t size, std::string what)
      : data_(data), size_(size), what_(std::move(what)) {}

  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>, "ByteReader::get takes numbers");
    need(sizeof(T));
    T value;
    std::memcpy(&value, data_ + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  bool getBool() {
    const auto v = get<std::uint8_t>();
    if (v > 1) fail("a flag is " + std::to_string(v) + ", not 0 or 1");
    return v == 1;
  }
  std::string getString() {
    const std::size_t n = count(1);
    std::string text(reinterpret_cast<const char*>(data_ + at_), n);
    at_ += n;
    return text;
  }
  template <typename T>
  std::vector<T> getArray() {
    const std::size_t n = count(sizeof(T));
    std::vector<T> values(n);
    if (n > 0) std::memcpy(values.data(), data_ + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return values;
  }
  // A count of items of `item_bytes` each that must fit in what is left.
  std::size_t count(std::size_t item_bytes) {
    const auto n = get<std::uint64_t>();
    if (item_bytes > 0 && n > (size_ - at_) / item_bytes) {
      fail("a count of " + std::to_string(n) + " items runs past its end");
    }
    return static_cast<std::size_t>(n);
  }
  // The buffer must start with `marker` (its magic number and version, in the writer's
  // byte order).
  void requireMarker(std::uint32_t marker) {
    const auto got = get<std::uint32_t>();
    if (got != marker) fail("it does not start with this build's marker (another program or version wrote it)");
  }
  void requireEnd() const {
    if (at_ != size_) fail(std::to_string(size_ - at_) + " bytes are left over at its end");
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(what_ + ": " + why + " (at byte " + std::to_string(at_) + " of " + std::to_string(size_) + ")");
  }

 private:
  void need(std::size_t n) const {
    if (n > size_ - at_) fail("it ends early");
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
  std::string what_;
};

}  // namespace room_reverb::core

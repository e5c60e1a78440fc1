// SPDX-License-Identifier: MIT
// Little-endian fields read from a span of bytes with every length checked against what is left:
// the containers' records (ROS 1 bags, MCAP) state lengths that a damaged file can get wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "dsm/util/check.h"

namespace dsm {

class ByteSpan {
 public:
  // `what` names the bytes in errors ("file.bag: the chunk at 4117").
  ByteSpan(const uint8_t* data, size_t size, std::string what) : data_(data), size_(size), what_(std::move(what)) {}

  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }
  size_t position() const { return pos_; }
  size_t remaining() const { return size_ - pos_; }
  bool done() const { return pos_ == size_; }
  const std::string& what() const { return what_; }

  const uint8_t* Take(uint64_t n) {
    if (n > remaining()) {
      throw InputError(what_ + ": a length of " + std::to_string(n) + " bytes where " + std::to_string(remaining()) +
                       " are left");
    }
    const uint8_t* p = data_ + pos_;
    pos_ += static_cast<size_t>(n);
    return p;
  }
  template <typename T>
  T Get() {
    T value;
    std::memcpy(&value, Take(sizeof(T)), sizeof(T));
    return value;
  }
  uint8_t U8() { return Get<uint8_t>(); }
  uint16_t U16() { return Get<uint16_t>(); }
  uint32_t U32() { return Get<uint32_t>(); }
  uint64_t U64() { return Get<uint64_t>(); }
  // `n` bytes as a span of their own, named `what`.
  ByteSpan Sub(uint64_t n, const std::string& what) { return ByteSpan(Take(n), static_cast<size_t>(n), what); }
  std::string String(uint64_t n) {
    const uint8_t* p = Take(n);
    return std::string(reinterpret_cast<const char*>(p), static_cast<size_t>(n));
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string what_;
};

}  // namespace dsm

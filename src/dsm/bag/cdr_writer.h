// SPDX-License-Identifier: MIT
// A ROS 2 message written in CDR (little-endian, XCDR1 as rmw writes it; the reading side is
// wire.h): the encapsulation header 0x00 0x01 0x00 0x00, then each field in the definition's
// order, every primitive aligned to its size counted from the end of that header.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dsm {

class CdrWriter {
 public:
  CdrWriter() : bytes_{0x00, 0x01, 0x00, 0x00} {}

  void U8(uint8_t v) { Put(v); }
  void U32(uint32_t v) { Put(v); }
  void I32(int32_t v) { Put(v); }
  void F32(float v) { Put(v); }
  void F64(double v) { Put(v); }
  // A string: its length with the closing NUL, the characters, the NUL.
  void String(const std::string& s);
  // builtin_interfaces/Time: int32 sec, uint32 nanosec.
  void Time(int64_t t_ns);
  // std_msgs/Header: the stamp, then frame_id.
  void Header(int64_t t_ns, const std::string& frame_id) {
    Time(t_ns);
    String(frame_id);
  }
  // A sequence's count (its elements follow).
  void Count(size_t n) { U32(static_cast<uint32_t>(n)); }
  // uint8[]: the count, then the bytes.
  void Bytes(const uint8_t* data, size_t size);

  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t> Take() { return std::move(bytes_); }

 private:
  template <typename T>
  void Put(T v);

  std::vector<uint8_t> bytes_;
};

}  // namespace dsm

// SPDX-License-Identifier: MIT
// The two ways ROS serializes a message, read field by field in the message definition's order.
//   ROS 1  little-endian, packed (no alignment); a string or a variable-length array is a uint32
//          count followed by its elements; a time is uint32 sec, uint32 nsec; std_msgs/Header
//          starts with a uint32 seq.
//   CDR    (ROS 2; XCDR1 as rmw writes it) a 4-byte encapsulation header (0x00 0x00: big-endian,
//          0x00 0x01: little-endian), then each primitive aligned to its size counted from the
//          end of that header; a string is a uint32 length that counts a closing NUL; a sequence
//          a uint32 count; builtin_interfaces/Time is int32 sec, uint32 nanosec; std_msgs/Header
//          has no seq.
// Fixed-length arrays have no count in either.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dsm {

enum class WireFormat { kRos1, kCdr };

class WireReader {
 public:
  // Reads `size` bytes at `data` (not copied: they must outlive the reader). `what` names the
  // message in errors ("file.bag /cam0/image_raw message 12"). Throws InputError for a CDR message
  // whose encapsulation header is not plain CDR.
  WireReader(const uint8_t* data, size_t size, WireFormat format, std::string what);

  WireFormat format() const { return format_; }
  uint8_t U8();
  uint32_t U32();
  int32_t I32();
  double F64();
  std::string String();
  // A time or duration in nanoseconds.
  int64_t Time();
  // std_msgs/Header: its stamp (ns) into *stamp_ns, its frame_id returned.
  std::string Header(int64_t* stamp_ns);
  // float64[n] (fixed length) into out.
  void F64Array(double* out, size_t n);
  // float64[] (a sequence).
  std::vector<double> F64Sequence();
  // uint8[] (a sequence): a view of the bytes inside the message.
  const uint8_t* ByteSequence(size_t* size);
  // The count of a sequence whose elements take at least `min_element_bytes` each (checked
  // against what is left, so that a corrupt count is an error, not a huge allocation).
  uint32_t SequenceCount(size_t min_element_bytes);

  // Everything left unread (messages may carry fields after the ones read).
  size_t remaining() const { return size_ - pos_; }

 private:
  void Align(size_t n);
  const uint8_t* Take(size_t n);
  template <typename T>
  T Primitive();

  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  size_t origin_ = 0;  // CDR: where alignment counts from (after the encapsulation header).
  bool big_endian_ = false;
  WireFormat format_;
  std::string what_;
};

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/bag/wire.h"

#include <cstring>

#include "dsm/util/check.h"

namespace dsm {

WireReader::WireReader(const uint8_t* data, size_t size, WireFormat format, std::string what)
    : data_(data), size_(size), format_(format), what_(std::move(what)) {
  if (format_ == WireFormat::kCdr) {
    if (size_ < 4) throw InputError(what_ + ": shorter than a CDR encapsulation header");
    if (data_[0] != 0 || data_[1] > 1) {
      throw InputError(what_ + ": not plain CDR (encapsulation " + std::to_string(data_[0]) + " " +
                       std::to_string(data_[1]) + ")");
    }
    big_endian_ = data_[1] == 0;
    pos_ = origin_ = 4;
  }
}

void WireReader::Align(size_t n) {
  if (format_ != WireFormat::kCdr) return;
  const size_t offset = (pos_ - origin_) % n;
  if (offset != 0) Take(n - offset);
}

const uint8_t* WireReader::Take(size_t n) {
  if (n > size_ - pos_) throw InputError(what_ + ": the message ends early (" + std::to_string(size_) + " bytes)");
  const uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

template <typename T>
T WireReader::Primitive() {
  Align(sizeof(T));
  uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, Take(sizeof(T)), sizeof(T));
  if (big_endian_) {
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

uint8_t WireReader::U8() { return Primitive<uint8_t>(); }
uint32_t WireReader::U32() { return Primitive<uint32_t>(); }
int32_t WireReader::I32() { return Primitive<int32_t>(); }
double WireReader::F64() { return Primitive<double>(); }

std::string WireReader::String() {
  const uint32_t length = U32();
  const char* chars = reinterpret_cast<const char*>(Take(length));
  if (format_ == WireFormat::kCdr) {
    if (length == 0 || chars[length - 1] != '\0') throw InputError(what_ + ": a CDR string without its closing NUL");
    return std::string(chars, length - 1);
  }
  return std::string(chars, length);
}

int64_t WireReader::Time() {
  const int64_t sec = format_ == WireFormat::kCdr ? I32() : static_cast<int64_t>(U32());
  const int64_t nsec = U32();
  if (nsec >= 1000000000) throw InputError(what_ + ": a time with " + std::to_string(nsec) + " nanoseconds");
  return sec * 1000000000 + nsec;
}

std::string WireReader::Header(int64_t* stamp_ns) {
  if (format_ == WireFormat::kRos1) U32();  // seq
  *stamp_ns = Time();
  return String();
}

void WireReader::F64Array(double* out, size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] = F64();
}

uint32_t WireReader::SequenceCount(size_t min_element_bytes) {
  const uint32_t count = U32();
  if (min_element_bytes > 0 && count > remaining() / min_element_bytes) {
    throw InputError(what_ + ": a sequence of " + std::to_string(count) + " elements in a message of " +
                     std::to_string(size_) + " bytes");
  }
  return count;
}

std::vector<double> WireReader::F64Sequence() {
  std::vector<double> values(SequenceCount(8));
  for (double& v : values) v = F64();
  return values;
}

const uint8_t* WireReader::ByteSequence(size_t* size) {
  *size = SequenceCount(1);
  return Take(*size);
}

}  // namespace dsm

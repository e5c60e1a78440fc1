// SPDX-License-Identifier: MIT
#include "dsm/bag/cdr_writer.h"

#include <cstring>

namespace dsm {

template <typename T>
void CdrWriter::Put(T v) {
  while ((bytes_.size() - 4) % sizeof(T) != 0) bytes_.push_back(0);
  const size_t at = bytes_.size();
  bytes_.resize(at + sizeof(T));
  std::memcpy(bytes_.data() + at, &v, sizeof(T));  // Little-endian hosts only (x86-64, arm64).
}

void CdrWriter::String(const std::string& s) {
  U32(static_cast<uint32_t>(s.size() + 1));
  bytes_.insert(bytes_.end(), s.begin(), s.end());
  bytes_.push_back(0);
}

void CdrWriter::Time(int64_t t_ns) {
  int64_t sec = t_ns / 1000000000;
  int64_t nsec = t_ns % 1000000000;
  if (nsec < 0) {
    sec -= 1;
    nsec += 1000000000;
  }
  I32(static_cast<int32_t>(sec));
  U32(static_cast<uint32_t>(nsec));
}

void CdrWriter::Bytes(const uint8_t* data, size_t size) {
  Count(size);
  bytes_.insert(bytes_.end(), data, data + size);
}

template void CdrWriter::Put<uint8_t>(uint8_t);
template void CdrWriter::Put<uint32_t>(uint32_t);
template void CdrWriter::Put<int32_t>(int32_t);
template void CdrWriter::Put<float>(float);
template void CdrWriter::Put<double>(double);

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/io/encoded_image_check.h"

#include <zlib.h>

#include <cstring>

namespace dsm {

namespace {

uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

std::string CheckPng(const std::vector<uint8_t>& b) {
  size_t pos = sizeof(kPngSignature);
  while (pos < b.size()) {
    if (b.size() - pos < 12) return "truncated PNG: incomplete chunk at byte " + std::to_string(pos);
    const uint32_t length = BigEndian32(&b[pos]);
    const std::string type(reinterpret_cast<const char*>(&b[pos + 4]), 4);
    if (length > b.size() - pos - 12) return "truncated PNG: chunk " + type + " at byte " + std::to_string(pos) + " is cut off";
    const uint32_t stored = BigEndian32(&b[pos + 8 + length]);
    if (crc32(0L, &b[pos + 4], 4 + length) != stored) {
      return "corrupt PNG: chunk " + type + " at byte " + std::to_string(pos) + " fails its CRC";
    }
    if (type == "IEND") return "";
    pos += 12 + length;
  }
  return "truncated PNG: no IEND chunk";
}

std::string CheckJpeg(const std::vector<uint8_t>& b) {
  size_t end = b.size();
  while (end > 2 && b[end - 1] == 0) --end;
  if (end < 4 || b[end - 2] != 0xFF || b[end - 1] != 0xD9) return "truncated JPEG: no end-of-image marker";
  return "";
}

}  // namespace

std::string CheckEncodedImage(const std::vector<uint8_t>& bytes) {
  if (bytes.empty()) return "empty file";
  if (bytes.size() >= sizeof(kPngSignature) && std::memcmp(bytes.data(), kPngSignature, sizeof(kPngSignature)) == 0)
    return CheckPng(bytes);
  if (bytes.size() >= 2 && bytes[0] == 0xFF && bytes[1] == 0xD8) return CheckJpeg(bytes);
  return "";
}

}  // namespace dsm

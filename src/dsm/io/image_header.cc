// SPDX-License-Identifier: MIT
#include "dsm/io/image_header.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <map>

#include "dsm/util/check.h"

namespace dsm {

namespace {

// Bounds-checked reads of one header; every failure is an InputError naming the file.
struct HeaderBytes {
  const std::vector<uint8_t>& b;
  const std::string& source;
  const char* format = "";
  bool big_endian = true;

  [[noreturn]] void Fail(const std::string& why) const { throw InputError(source + ": " + why); }
  void Need(size_t pos, size_t n) const {
    if (pos > b.size() || n > b.size() - pos) Fail(std::string("truncated ") + format + " header");
  }
  uint32_t U8(size_t pos) const {
    Need(pos, 1);
    return b[pos];
  }
  uint32_t U16(size_t pos) const {
    Need(pos, 2);
    return big_endian ? (uint32_t{b[pos]} << 8) | b[pos + 1] : b[pos] | (uint32_t{b[pos + 1]} << 8);
  }
  uint32_t U32(size_t pos) const {
    const uint32_t first = U16(pos), second = U16(pos + 2);
    return big_endian ? (first << 16) | second : first | (second << 16);
  }
  bool StartsWith(std::initializer_list<uint8_t> signature) const {
    return b.size() >= signature.size() && std::equal(signature.begin(), signature.end(), b.begin());
  }
  // Pixel data of an uncompressed format: `needed` bytes from `offset` must be in the file.
  void NeedPixels(uint64_t offset, uint64_t needed, const ImageHeader& header) const {
    if (offset > b.size() || needed > b.size() - offset)
      Fail(std::string("truncated ") + format + ": " + std::to_string(header.width) + "x" +
           std::to_string(header.height) + " pixels need " + std::to_string(needed) + " bytes from byte " +
           std::to_string(offset) + ", the file has " + std::to_string(b.size()));
  }
};

bool IsWhiteSpace(uint32_t c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

ImageHeader Sized(const HeaderBytes& h, uint64_t width, uint64_t height) {
  if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide ||
      width * height > kMaxImagePixels)
    h.Fail(std::string("the ") + h.format + " header declares " + std::to_string(width) + "x" +
           std::to_string(height) + " pixels (each side 1 to " + std::to_string(kMaxImageSide) + ", at most " +
           std::to_string(kMaxImagePixels) + " pixels)");
  return {h.format, static_cast<uint32_t>(width), static_cast<uint32_t>(height)};
}

// PNG: signature (8 bytes), then the IHDR chunk: length (4), "IHDR", width (4), height (4), ...
ImageHeader ReadPng(HeaderBytes& h) {
  h.Need(12, 4);
  if (std::memcmp(&h.b[12], "IHDR", 4) != 0) h.Fail("the PNG does not start with an IHDR chunk");
  return Sized(h, h.U32(16), h.U32(20));
}

// JPEG: SOI, then segments FF <marker> [<length, 2 bytes, counting itself> <data>] until a
// start-of-frame segment: length (2), sample precision (1), height (2), width (2), ...
ImageHeader ReadJpeg(HeaderBytes& h) {
  size_t pos = 2;
  for (;;) {
    if (h.U8(pos) != 0xFF) h.Fail("the JPEG has no segment marker at byte " + std::to_string(pos));
    while (h.U8(pos) == 0xFF) ++pos;  // Fill bytes.
    const uint32_t marker = h.U8(pos++);
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // Markers without a segment.
    if (marker == 0xD9 || marker == 0xDA) h.Fail("the JPEG has no frame header before its scan");
    const uint32_t length = h.U16(pos);
    if (length < 2) h.Fail("the JPEG has a segment of length " + std::to_string(length) + " at byte " + std::to_string(pos));
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame) return Sized(h, h.U16(pos + 5), h.U16(pos + 3));
    pos += length;
  }
}

// PNM: "P5" (grey) or "P6" (RGB) in binary, "P2" / "P3" in ASCII; then width, height and maxval as
// decimal numbers separated by white space and '#' comments, then one white space byte and the samples
// (two bytes each when maxval > 255).
ImageHeader ReadPnm(HeaderBytes& h) {
  size_t pos = 2;
  const auto number = [&](const char* what) {
    for (;;) {
      const uint32_t c = h.U8(pos);
      if (c == '#') {
        while (h.U8(pos) != '\n' && h.U8(pos) != '\r') ++pos;
      } else if (IsWhiteSpace(c)) {
        ++pos;
      } else {
        break;
      }
    }
    if (h.U8(pos) < '0' || h.U8(pos) > '9') h.Fail(std::string("the PNM header has no ") + what);
    uint64_t value = 0;
    for (; pos < h.b.size() && h.b[pos] >= '0' && h.b[pos] <= '9'; ++pos)
      value = std::min<uint64_t>(value * 10 + (h.b[pos] - '0'), uint64_t{1} << 40);
    return value;
  };
  const uint64_t width = number("width"), height = number("height"), maxval = number("maxval");
  const ImageHeader header = Sized(h, width, height);
  if (maxval == 0 || maxval > 65535) h.Fail("the PNM header has maxval " + std::to_string(maxval) + " (1 to 65535)");
  h.Need(pos, 1);
  ++pos;
  const uint64_t channels = (h.b[1] == '3' || h.b[1] == '6') ? 3 : 1;
  const bool ascii = h.b[1] == '2' || h.b[1] == '3';
  // An ASCII sample is at least one digit.
  const uint64_t bytes_per_sample = ascii ? 1 : (maxval > 255 ? 2 : 1);
  h.NeedPixels(pos, width * height * channels * bytes_per_sample, header);
  return header;
}

// BMP (little endian): "BM", file size (4), reserved (4), pixel data offset (4), then the DIB header:
// its size (4) and, in the 12-byte core header, width, height (2 each), planes (2), bits per pixel
// (2); in the info header (40 bytes or more), width, height (signed, 4 each; a negative height stores
// the rows top-down), planes (2), bits per pixel (2), compression (4). Uncompressed rows (BI_RGB = 0,
// BI_BITFIELDS = 3) are padded to 4 bytes.
ImageHeader ReadBmp(HeaderBytes& h) {
  h.big_endian = false;
  const uint32_t dib_size = h.U32(14);
  uint64_t width = 0, height = 0;
  uint32_t bits = 0, compression = 0;
  if (dib_size == 12) {
    width = h.U16(18);
    height = h.U16(20);
    bits = h.U16(24);
  } else if (dib_size >= 40) {
    const auto signed_width = static_cast<int32_t>(h.U32(18));
    const auto signed_height = static_cast<int32_t>(h.U32(22));
    width = signed_width > 0 ? static_cast<uint64_t>(signed_width) : 0;
    height = static_cast<uint64_t>(std::abs(static_cast<int64_t>(signed_height)));
    bits = h.U16(28);
    compression = h.U32(30);
  } else {
    h.Fail("the BMP has a " + std::to_string(dib_size) + "-byte DIB header (12, or 40 and more)");
  }
  const ImageHeader header = Sized(h, width, height);
  if (compression > 3) h.Fail("the BMP has compression " + std::to_string(compression) + " (0 to 3: none, RLE8, RLE4, bit fields)");
  if (compression == 0 || compression == 3) {
    if (bits != 1 && bits != 4 && bits != 8 && bits != 16 && bits != 24 && bits != 32)
      h.Fail("the BMP has " + std::to_string(bits) + " bits per pixel (1, 4, 8, 16, 24 or 32)");
    const uint64_t row_bytes = (width * bits + 31) / 32 * 4;
    h.NeedPixels(h.U32(10), row_bytes * height, header);
  }
  return header;
}

// TIFF: "II" (little endian) or "MM", 42, the first IFD's offset (4); the IFD: entry count (2), then
// 12-byte entries: tag (2), type (2: 3 SHORT, 4 LONG), count (4), value (4, a SHORT in its first two).
// Besides the size, the decoder allocates one strip (width x RowsPerStrip) or one tile (TileWidth x
// TileLength) at up to 4 bytes a pixel whatever the image's size, so that unit is bounded as the image
// is: a RowsPerStrip of 65535 on a 12090-wide image asks for 3.2 GB.
ImageHeader ReadTiff(HeaderBytes& h) {
  h.big_endian = h.b[0] == 'M';
  const size_t ifd = h.U32(4);
  const uint32_t entries = h.U16(ifd);
  constexpr uint32_t kWidth = 256, kLength = 257, kRowsPerStrip = 278, kTileWidth = 322, kTileLength = 323;
  std::map<uint32_t, uint64_t> value;  // The sizing tags present.
  for (uint32_t i = 0; i < entries; ++i) {
    const size_t entry = ifd + 2 + 12 * size_t{i};
    const uint32_t tag = h.U16(entry);
    if (tag != kWidth && tag != kLength && tag != kRowsPerStrip && tag != kTileWidth && tag != kTileLength) continue;
    const uint32_t type = h.U16(entry + 2);
    if (type != 3 && type != 4) h.Fail("the TIFF tag " + std::to_string(tag) + " has type " + std::to_string(type));
    // libtiff keeps the first of two equal tags: a second one would let the decoder see another size.
    if (value.count(tag) != 0) h.Fail("the TIFF has tag " + std::to_string(tag) + " twice");
    value[tag] = type == 3 ? h.U16(entry + 8) : h.U32(entry + 8);
  }
  const auto get = [&](uint32_t tag) { return value.count(tag) != 0 ? value.at(tag) : uint64_t{0}; };
  const ImageHeader header = Sized(h, get(kWidth), get(kLength));
  if (value.count(kTileWidth) != 0 || value.count(kTileLength) != 0) {
    const uint64_t tile = get(kTileWidth) * get(kTileLength);
    if (tile == 0 || tile > kMaxImagePixels)
      h.Fail("the TIFF declares tiles of " + std::to_string(get(kTileWidth)) + "x" +
             std::to_string(get(kTileLength)) + " pixels (1 to " + std::to_string(kMaxImagePixels) + " pixels)");
  } else {
    // No RowsPerStrip, 0 or 2^32 - 1: one strip of the whole image, as the size check bounds already.
    const uint64_t rows = get(kRowsPerStrip);
    if (rows != 0 && rows != 0xFFFFFFFF && header.width * rows > kMaxImagePixels)
      h.Fail("the TIFF declares strips of " + std::to_string(rows) + " rows of " + std::to_string(header.width) +
             " pixels (at most " + std::to_string(kMaxImagePixels) + " pixels a strip)");
  }
  return header;
}

}  // namespace

ImageHeader ReadImageHeader(const std::vector<uint8_t>& bytes, const std::string& source) {
  HeaderBytes h{bytes, source};
  // Whole signatures, as OpenCV's own decoders check them: a near miss would fall through to another
  // decoder that claims the bytes (HDR, DICOM, ...), which may believe a header asking for gigabytes.
  if (h.StartsWith({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A})) {
    h.format = "PNG";
    return ReadPng(h);
  }
  if (h.StartsWith({0xFF, 0xD8, 0xFF})) {
    h.format = "JPEG";
    return ReadJpeg(h);
  }
  const bool pnm = bytes.size() >= 3 && bytes[0] == 'P' && std::strchr("2356", bytes[1]) != nullptr &&
                   bytes[1] != 0 && IsWhiteSpace(bytes[2]);
  if (pnm) {
    h.format = "PNM";
    return ReadPnm(h);
  }
  if (h.StartsWith({'B', 'M'})) {
    h.format = "BMP";
    return ReadBmp(h);
  }
  if (h.StartsWith({'I', 'I', 42, 0}) || h.StartsWith({'M', 'M', 0, 42})) {
    h.format = "TIFF";
    return ReadTiff(h);
  }
  h.Fail("not a PNG, JPEG, PGM/PPM, BMP or TIFF image");
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
// The format and size an encoded image declares, read from its header before any decoder sees it.
//
// A decoder allocates width x height x channels for whatever a header claims, so a 50-byte file can
// ask for gigabytes. The readers here parse just enough of each format a dataset's images may be in
// to bound that:
//   PNG   IHDR, the first chunk (width, height as big-endian words at bytes 16 and 20);
//   JPEG  the segments up to the first start-of-frame marker (SOF0..SOF15 but DHT, JPG, DAC);
//   PNM   P2 / P3 / P5 / P6: width, height, maxval in ASCII, '#' comments between them;
//   BMP   the core (12-byte) or info (>= 40-byte) header; a negative height is top-down;
//   TIFF  the first IFD's ImageWidth (256) and ImageLength (257) tags, either byte order, and the
//         strip (RowsPerStrip, 278) or tile (TileWidth, TileLength: 322, 323) the decoder allocates.
// Formats that store pixels uncompressed (binary PNM, BMP without RLE) must also hold all of them:
// width x height x bytes per pixel, with BMP's rows padded to 4 bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dsm {

struct ImageHeader {
  std::string format;  // "PNG", "JPEG", "PNM", "BMP" or "TIFF".
  uint32_t width = 0;
  uint32_t height = 0;
};

// Every side of a decoded image is at most this (as CameraCalibration::Validate) ...
inline constexpr uint32_t kMaxImageSide = 16384;
// ... and it has at most this many pixels (64 Mpx: 8192 x 8192, 384 MB as 16-bit colour).
inline constexpr uint64_t kMaxImagePixels = uint64_t{1} << 26;

// The header of `bytes`, or an InputError naming `source`: not one of the five formats, a header
// cut off or inconsistent, a side of 0 or above kMaxImageSide, more than kMaxImagePixels pixels, or
// fewer pixel bytes than an uncompressed format needs.
ImageHeader ReadImageHeader(const std::vector<uint8_t>& bytes, const std::string& source);

}  // namespace dsm

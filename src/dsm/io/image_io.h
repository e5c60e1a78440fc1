// SPDX-License-Identifier: MIT
// Image files through OpenCV, converted to and from our Image<T>.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dsm/image/image.h"

namespace dsm {

// Decodes an encoded image (PNG, JPEG, PGM/PPM, BMP or TIFF) to 8-bit grey: colour is converted, 16 bit
// scaled down. Throws InputError naming `source` when it cannot be decoded: damaged files
// (encoded_image_check.h), other formats and sizes out of bounds (image_header.h), decoder failures.
Image<uint8_t> DecodeGray8(const std::vector<uint8_t>& bytes, const std::string& source);
Image<uint8_t> ReadGray8(const std::filesystem::path& path);

// Reads an image as grey float values (8 or 16 bit, or 32-bit float TIFF), with DecodeGray8's checks.
Image<float> ReadGrayFloat(const std::filesystem::path& path);

void WriteGray8(const std::filesystem::path& path, const Image<uint8_t>& image);
void WriteGray16(const std::filesystem::path& path, const Image<uint16_t>& image);
// 8-bit colour.
struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
};
void WriteRgb8(const std::filesystem::path& path, const Image<Rgb8>& image);
// 32-bit float TIFF (lossless).
void WriteFloatTiff(const std::filesystem::path& path, const Image<float>& image);

}  // namespace dsm

// SPDX-License-Identifier: MIT
// A cheap integrity check of an encoded image before it is decoded, so that a damaged file in a
// recording is reported once, in our words, instead of by the codec library (libpng and libjpeg
// print their own errors and warnings to stderr).
//
// PNG: the signature, then every chunk (length, type, data, CRC-32 of type + data) up to IEND must
// be complete and its CRC (zlib's crc32, the one PNG specifies) must match. JPEG: starts with SOI
// (FF D8) and ends with EOI (FF D9), trailing zero padding allowed. Other formats are left to the
// decoder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dsm {

// Empty when the bytes look intact, else why not (e.g. "truncated: no IEND chunk").
std::string CheckEncodedImage(const std::vector<uint8_t>& bytes);

}  // namespace dsm

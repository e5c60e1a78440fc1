// SPDX-License-Identifier: MIT
// OpenCV matrices to and from our 8-bit grey images (for the code that works through OpenCV).
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "dsm/image/image.h"

namespace dsm {

// An OpenCV header over `image`'s pixels: no copy, valid while `image` lives and unchanged.
inline cv::Mat Gray8View(const Image<uint8_t>& image) {
  return cv::Mat(image.height(), image.width(), CV_8UC1, const_cast<uint8_t*>(image.data()));
}

// Colour (BGR, BGRA) converted to grey, 16 bit scaled down; throws InputError naming `source` for
// other pixel types.
Image<uint8_t> MatToGray8(cv::Mat m, const std::string& source);

}  // namespace dsm

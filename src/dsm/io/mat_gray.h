// SPDX-License-Identifier: MIT
// OpenCV matrices to our 8-bit grey images (for the readers that decode through OpenCV).
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core/mat.hpp>

#include "dsm/image/image.h"

namespace dsm {

// Colour (BGR, BGRA) converted to grey, 16 bit scaled down; throws InputError naming `source` for
// other pixel types.
Image<uint8_t> MatToGray8(cv::Mat m, const std::string& source);

}  // namespace dsm

// SPDX-License-Identifier: MIT
// Image messages to 8-bit grey, as dsm reads image files (io/image_io.h): colour to grey with
// OpenCV's weights, 16 bit scaled by 1/257.
//   sensor_msgs/Image encodings: mono8, 8UC1, mono16, 16UC1 (either byte order), rgb8, bgr8,
//   rgba8, bgra8, and the Bayer patterns bayer_rggb8, bayer_bggr8, bayer_gbrg8, bayer_grbg8
//   (demosaiced to grey) and their 16-bit forms
//   sensor_msgs/CompressedImage: JPEG or PNG (what the bytes are, whatever `format` says)
#pragma once

#include <cstdint>
#include <string>

#include "dsm/bag/messages.h"
#include "dsm/image/image.h"

namespace dsm {

// Throws InputError naming `where` for an unknown encoding, or a size, step or data length that
// do not agree.
Image<uint8_t> ImageMessageToGray8(const ImageMessage& message, const std::string& where);
// Throws InputError naming `where` when the bytes do not decode.
Image<uint8_t> CompressedImageToGray8(const CompressedImageMessage& message, const std::string& where);

// Whether `encoding` is one ImageMessageToGray8 reads.
bool IsSupportedImageEncoding(const std::string& encoding);

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/bag/image_message.h"

#include <map>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "dsm/io/image_io.h"
#include "dsm/io/mat_gray.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

// An encoding's pixel layout and its conversion to one grey channel (-1: none needed).
struct Encoding {
  int cv_type;
  int to_gray;
};

// ROS names Bayer patterns by the first row's colours; OpenCV by the second row's.
const std::map<std::string, Encoding>& Encodings() {
  static const std::map<std::string, Encoding> encodings = {
      {"mono8", {CV_8UC1, -1}},
      {"8UC1", {CV_8UC1, -1}},
      {"mono16", {CV_16UC1, -1}},
      {"16UC1", {CV_16UC1, -1}},
      {"rgb8", {CV_8UC3, cv::COLOR_RGB2GRAY}},
      {"bgr8", {CV_8UC3, cv::COLOR_BGR2GRAY}},
      {"rgba8", {CV_8UC4, cv::COLOR_RGBA2GRAY}},
      {"bgra8", {CV_8UC4, cv::COLOR_BGRA2GRAY}},
      {"bayer_rggb8", {CV_8UC1, cv::COLOR_BayerBG2GRAY}},
      {"bayer_bggr8", {CV_8UC1, cv::COLOR_BayerRG2GRAY}},
      {"bayer_gbrg8", {CV_8UC1, cv::COLOR_BayerGR2GRAY}},
      {"bayer_grbg8", {CV_8UC1, cv::COLOR_BayerGB2GRAY}},
      {"bayer_rggb16", {CV_16UC1, cv::COLOR_BayerBG2GRAY}},
      {"bayer_bggr16", {CV_16UC1, cv::COLOR_BayerRG2GRAY}},
      {"bayer_gbrg16", {CV_16UC1, cv::COLOR_BayerGR2GRAY}},
      {"bayer_grbg16", {CV_16UC1, cv::COLOR_BayerGB2GRAY}},
  };
  return encodings;
}

}  // namespace

bool IsSupportedImageEncoding(const std::string& encoding) { return Encodings().count(encoding) > 0; }

Image<uint8_t> ImageMessageToGray8(const ImageMessage& message, const std::string& where) {
  const auto it = Encodings().find(message.encoding);
  if (it == Encodings().end()) {
    std::string known;
    for (const auto& [name, encoding] : Encodings()) known += (known.empty() ? "" : ", ") + name;
    throw InputError(where + ": image encoding '" + message.encoding + "' is not one dsm reads (" + known + ")");
  }
  const Encoding encoding = it->second;
  const size_t pixel_bytes = CV_ELEM_SIZE(encoding.cv_type);
  if (message.width == 0 || message.height == 0 || message.width > 1u << 15 || message.height > 1u << 15) {
    throw InputError(where + ": an image of " + std::to_string(message.width) + "x" + std::to_string(message.height));
  }
  if (message.step < message.width * pixel_bytes || uint64_t{message.step} * message.height > message.size) {
    throw InputError(where + ": step " + std::to_string(message.step) + " and " + std::to_string(message.size) +
                     " bytes do not hold a " + std::to_string(message.width) + "x" + std::to_string(message.height) +
                     " " + message.encoding + " image");
  }
  cv::Mat m(static_cast<int>(message.height), static_cast<int>(message.width), encoding.cv_type,
            const_cast<uint8_t*>(message.data), message.step);
  const bool swap_bytes = message.big_endian && CV_MAT_DEPTH(encoding.cv_type) == CV_16U;
  if (swap_bytes) {
    m = m.clone();
    for (int y = 0; y < m.rows; ++y) {
      uint16_t* row = m.ptr<uint16_t>(y);
      for (int x = 0; x < m.cols; ++x) row[x] = static_cast<uint16_t>((row[x] >> 8) | (row[x] << 8));
    }
  }
  if (encoding.to_gray >= 0) {
    cv::Mat gray;
    cv::cvtColor(m, gray, encoding.to_gray);
    m = gray;
  }
  return MatToGray8(m, where);
}

Image<uint8_t> CompressedImageToGray8(const CompressedImageMessage& message, const std::string& where) {
  return DecodeGray8(std::vector<uint8_t>(message.data, message.data + message.size), where);
}

}  // namespace dsm

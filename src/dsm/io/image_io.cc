// SPDX-License-Identifier: MIT
#include "dsm/io/image_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <initializer_list>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dsm/io/encoded_image_check.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

cv::Mat ToGrayOneChannel(cv::Mat m) {
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  if (m.channels() == 4) cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
  return m;
}

template <typename T>
Image<T> FromMat(const cv::Mat& m) {
  Image<T> out(m.cols, m.rows);
  for (int y = 0; y < m.rows; ++y) std::memcpy(out.Row(y), m.ptr<T>(y), sizeof(T) * m.cols);
  return out;
}

Image<uint8_t> ToGray8(cv::Mat m, const std::string& source) {
  if (m.empty()) throw InputError(source + ": cannot decode the image (missing, corrupt or unsupported)");
  m = ToGrayOneChannel(m);
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  if (m.depth() != CV_8U || m.channels() != 1) throw InputError(source + ": unsupported pixel type");
  return FromMat<uint8_t>(m);
}

void Write(const std::filesystem::path& path, const cv::Mat& m) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), m);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path.string() + ": cannot write the image");
}

}  // namespace

// The formats a dataset's images may be in, by their first bytes: PNG, JPEG, PGM / PPM, BMP, TIFF.
// Anything else is refused before OpenCV tries its other decoders (HDR, DICOM, ...), which print
// their own errors and may believe a header asking for gigabytes.
bool IsImageFormat(const std::vector<uint8_t>& b) {
  const auto starts = [&](std::initializer_list<uint8_t> sig) {
    return b.size() >= sig.size() && std::equal(sig.begin(), sig.end(), b.begin());
  };
  // Whole signatures, as OpenCV's own decoders check them: a near miss would fall through to the
  // next decoder that claims the bytes (GDCM asserts on some).
  const bool pnm = b.size() >= 3 && b[0] == 'P' && (b[1] == '2' || b[1] == '3' || b[1] == '5' || b[1] == '6') &&
                   std::isspace(b[2]);
  return starts({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}) || starts({0xFF, 0xD8, 0xFF}) || pnm ||
         starts({'B', 'M'}) || starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42});
}

Image<uint8_t> DecodeGray8(const std::vector<uint8_t>& bytes, const std::string& source) {
  const std::string damage = CheckEncodedImage(bytes);
  if (!damage.empty()) throw InputError(source + ": cannot decode the image (" + damage + ")");
  if (!IsImageFormat(bytes)) throw InputError(source + ": not a PNG, JPEG, PGM/PPM, BMP or TIFF image");
  constexpr uint32_t kMaxSide = 16384;  // As CameraCalibration::Validate.
  if (bytes[0] == 0x89 && bytes.size() >= 24) {
    // PNG: IHDR is the first chunk; width and height are its first two big-endian words.
    const auto word = [&](size_t i) {
      return (uint32_t{bytes[i]} << 24) | (uint32_t{bytes[i + 1]} << 16) | (uint32_t{bytes[i + 2]} << 8) | bytes[i + 3];
    };
    if (word(16) > kMaxSide || word(20) > kMaxSide)
      throw InputError(source + ": the image claims " + std::to_string(word(16)) + "x" + std::to_string(word(20)) +
                       " pixels (at most " + std::to_string(kMaxSide) + " a side)");
  }
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    m = cv::Mat();
  }
  return ToGray8(m, source);
}

Image<uint8_t> ReadGray8(const std::filesystem::path& path) {
  // A folder opens as a stream but fails on the first read (with an exception): check first, without
  // throwing on names the file system refuses (too long, ...).
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw InputError(path.string() + ": no such image file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the image");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string() + ": read error");
  return DecodeGray8(bytes, path.string());
}

Image<float> ReadGrayFloat(const std::filesystem::path& path) {
  cv::Mat m;
  try {
    m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    m = cv::Mat();
  }
  if (m.empty()) throw InputError(path.string() + ": cannot read the image (missing, corrupt or unsupported)");
  m = ToGrayOneChannel(m);
  m.convertTo(m, CV_32F);
  return FromMat<float>(m);
}

void WriteGray8(const std::filesystem::path& path, const Image<uint8_t>& image) {
  Write(path, cv::Mat(image.height(), image.width(), CV_8UC1, const_cast<uint8_t*>(image.data())));
}

void WriteGray16(const std::filesystem::path& path, const Image<uint16_t>& image) {
  Write(path, cv::Mat(image.height(), image.width(), CV_16UC1, const_cast<uint16_t*>(image.data())));
}

void WriteRgb8(const std::filesystem::path& path, const Image<Rgb8>& image) {
  cv::Mat bgr;
  cv::cvtColor(cv::Mat(image.height(), image.width(), CV_8UC3, const_cast<Rgb8*>(image.data())), bgr,
               cv::COLOR_RGB2BGR);
  Write(path, bgr);
}

void WriteFloatTiff(const std::filesystem::path& path, const Image<float>& image) {
  Write(path, cv::Mat(image.height(), image.width(), CV_32FC1, const_cast<float*>(image.data())));
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/io/image_io.h"
#include "dsm/io/mat_gray.h"

#include <cstring>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dsm/io/encoded_image_check.h"
#include "dsm/io/image_header.h"
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


void Write(const std::filesystem::path& path, const cv::Mat& m) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), m);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path.string() + ": cannot write the image");
}

// Integrity (encoded_image_check.h), then format and size (image_header.h), then OpenCV.
cv::Mat Decode(const std::vector<uint8_t>& bytes, const std::string& source) {
  const std::string damage = CheckEncodedImage(bytes);
  if (!damage.empty()) throw InputError(source + ": cannot decode the image (" + damage + ")");
  const ImageHeader header = ReadImageHeader(bytes, source);
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    m = cv::Mat();
  }
  if (m.empty()) throw InputError(source + ": cannot decode the " + header.format + " image (corrupt or unsupported)");
  if (static_cast<uint32_t>(m.cols) != header.width || static_cast<uint32_t>(m.rows) != header.height)
    throw InputError(source + ": the " + header.format + " image decodes to " + std::to_string(m.cols) + "x" +
                     std::to_string(m.rows) + " pixels, its header declares " + std::to_string(header.width) + "x" +
                     std::to_string(header.height));
  return m;
}

std::vector<uint8_t> ReadFile(const std::filesystem::path& path) {
  // A folder opens as a stream but fails on the first read (with an exception): check first, without
  // throwing on names the file system refuses (too long, ...).
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw InputError(path.string() + ": no such image file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the image");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (!in || size < 0) throw InputError(path.string() + ": read error");
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), size);
  // A file that shrank meanwhile reads short: what was read is decoded (and fails if cut).
  bytes.resize(static_cast<size_t>(in.gcount()));
  if (in.bad()) throw InputError(path.string() + ": read error");
  return bytes;
}

}  // namespace

Image<uint8_t> MatToGray8(cv::Mat m, const std::string& source) {
  m = ToGrayOneChannel(m);
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  if (m.depth() != CV_8U || m.channels() != 1) throw InputError(source + ": unsupported pixel type");
  return FromMat<uint8_t>(m);
}

Image<uint8_t> DecodeGray8(const std::vector<uint8_t>& bytes, const std::string& source) {
  return MatToGray8(Decode(bytes, source), source);
}

Image<uint8_t> ReadGray8(const std::filesystem::path& path) { return DecodeGray8(ReadFile(path), path.string()); }

Image<float> ReadGrayFloat(const std::filesystem::path& path) {
  cv::Mat m = ToGrayOneChannel(Decode(ReadFile(path), path.string()));
  m.convertTo(m, CV_32F);
  return FromMat<float>(m);
}

void WriteGray8(const std::filesystem::path& path, const Image<uint8_t>& image) {
  Write(path, Gray8View(image));
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

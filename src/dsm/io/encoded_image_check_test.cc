// SPDX-License-Identifier: MIT
#include "dsm/io/encoded_image_check.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "dsm/io/image_io.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

std::vector<uint8_t> Encoded(const std::string& ext) {
  cv::Mat m(48, 64, CV_8UC1);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x) m.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 7 + y * 13) % 251);
  std::vector<uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, m, bytes));
  return bytes;
}

TEST(EncodedImageCheck, IntactImagesPass) {
  EXPECT_EQ(CheckEncodedImage(Encoded(".png")), "");
  EXPECT_EQ(CheckEncodedImage(Encoded(".jpg")), "");
  std::vector<uint8_t> padded = Encoded(".jpg");
  padded.insert(padded.end(), 3, 0);
  EXPECT_EQ(CheckEncodedImage(padded), "");
  EXPECT_EQ(DecodeGray8(Encoded(".png"), "x.png").width(), 64);
}

TEST(EncodedImageCheck, DamagedPngsAreNamed) {
  const std::vector<uint8_t> png = Encoded(".png");
  EXPECT_EQ(CheckEncodedImage({}), "empty file");
  const std::vector<uint8_t> half(png.begin(), png.begin() + png.size() / 2);
  EXPECT_NE(CheckEncodedImage(half).find("truncated PNG"), std::string::npos);
  const std::vector<uint8_t> no_end(png.begin(), png.end() - 12);  // IEND is the last 12 bytes.
  EXPECT_EQ(CheckEncodedImage(no_end), "truncated PNG: no IEND chunk");
  std::vector<uint8_t> flipped = png;
  flipped[png.size() / 2] ^= 0x5A;
  EXPECT_NE(CheckEncodedImage(flipped).find("fails its CRC"), std::string::npos);
  try {
    DecodeGray8(flipped, "frame_0042.png");
    FAIL() << "a corrupt PNG decoded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_0042.png: cannot decode the image (corrupt PNG"), std::string::npos)
        << e.what();
  }
}

TEST(EncodedImageCheck, TruncatedJpegIsNamed) {
  const std::vector<uint8_t> jpg = Encoded(".jpg");
  const std::vector<uint8_t> half(jpg.begin(), jpg.begin() + jpg.size() / 2);
  EXPECT_EQ(CheckEncodedImage(half), "truncated JPEG: no end-of-image marker");
}

}  // namespace
}  // namespace dsm

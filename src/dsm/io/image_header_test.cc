// SPDX-License-Identifier: MIT
#include "dsm/io/image_header.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "dsm/io/image_io.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

std::vector<uint8_t> Encoded(const std::string& ext, int type = CV_8UC1, std::vector<int> params = {}) {
  cv::Mat m(48, 64, type);
  cv::randu(m, 0, type == CV_16UC1 ? 65535 : 255);
  std::vector<uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(ext, m, bytes, params));
  return bytes;
}

// The message of the InputError that reading the header throws ("" when it throws none).
std::string Refusal(const std::vector<uint8_t>& bytes) {
  try {
    ReadImageHeader(bytes, "img");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void PutLittle32(std::vector<uint8_t>& b, size_t pos, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[pos + i] = static_cast<uint8_t>(v >> (8 * i));
}

TEST(ImageHeader, ReadsTheSizeOfEveryFormatOpenCvWrites) {
  const struct {
    std::string ext, format;
    int type;
    std::vector<int> params;
  } cases[] = {
      {".png", "PNG", CV_8UC1, {}},       {".png", "PNG", CV_16UC1, {}},
      {".png", "PNG", CV_8UC3, {}},       {".jpg", "JPEG", CV_8UC1, {}},
      {".jpg", "JPEG", CV_8UC3, {}},      {".pgm", "PNM", CV_8UC1, {}},
      {".pgm", "PNM", CV_16UC1, {}},      {".ppm", "PNM", CV_8UC3, {}},
      {".pgm", "PNM", CV_8UC1, {cv::IMWRITE_PXM_BINARY, 0}},
      {".bmp", "BMP", CV_8UC1, {}},       {".bmp", "BMP", CV_8UC3, {}},
      {".tiff", "TIFF", CV_8UC1, {}},     {".tiff", "TIFF", CV_16UC1, {}},
  };
  for (const auto& c : cases) {
    const std::vector<uint8_t> bytes = Encoded(c.ext, c.type, c.params);
    const ImageHeader header = ReadImageHeader(bytes, "img" + c.ext);
    EXPECT_EQ(header.format, c.format) << c.ext;
    EXPECT_EQ(header.width, 64u) << c.ext;
    EXPECT_EQ(header.height, 48u) << c.ext;
    const Image<uint8_t> image = DecodeGray8(bytes, "img" + c.ext);
    EXPECT_EQ(image.width(), 64) << c.ext;
    EXPECT_EQ(image.height(), 48) << c.ext;
  }
}

TEST(ImageHeader, OtherFormatsAreRefused) {
  EXPECT_NE(Refusal({'G', 'I', 'F', '8', '9', 'a', 1, 0, 1, 0}).find("not a PNG, JPEG"), std::string::npos);
  EXPECT_NE(Refusal({'P', '4', '\n', '8', ' ', '8', '\n', 0}).find("not a PNG, JPEG"), std::string::npos);
  EXPECT_NE(Refusal({'#', '?', 'R', 'A', 'D', 'I', 'A', 'N', 'C', 'E'}).find("not a PNG"), std::string::npos);
  std::vector<uint8_t> embedded_jpeg = Encoded(".bmp");
  PutLittle32(embedded_jpeg, 30, 4);  // BI_JPEG: a BMP around a JPEG, which OpenCV does not read.
  EXPECT_NE(Refusal(embedded_jpeg).find("the BMP has compression 4"), std::string::npos) << Refusal(embedded_jpeg);
}

// A header may claim any size; the claim is checked before a decoder allocates for it.
TEST(ImageHeader, SizesOutOfBoundsAreRefusedInEveryFormat) {
  std::vector<uint8_t> png = Encoded(".png");
  png[16] = 0x7F;  // Width 0x7F000040.
  EXPECT_NE(Refusal(png).find("img: the PNG header declares 2130706496x48 pixels"), std::string::npos) << Refusal(png);

  std::vector<uint8_t> jpg = Encoded(".jpg");
  for (size_t i = 2; i + 8 < jpg.size(); ++i) {
    if (jpg[i] == 0xFF && jpg[i + 1] == 0xC0) {  // SOF0: FF C0, length (2), precision (1), height (2), width.
      jpg[i + 5] = 0;
      jpg[i + 6] = 0;
      break;
    }
  }
  EXPECT_NE(Refusal(jpg).find("the JPEG header declares 64x0 pixels"), std::string::npos) << Refusal(jpg);

  const std::string pgm = "P5\n# a comment\n16385 2\n255\n";
  EXPECT_NE(Refusal({pgm.begin(), pgm.end()}).find("declares 16385x2"), std::string::npos);

  std::vector<uint8_t> bmp = Encoded(".bmp");
  PutLittle32(bmp, 18, 0xFFFF9FFF);  // A negative width.
  EXPECT_NE(Refusal(bmp).find("the BMP header declares 0x48 pixels"), std::string::npos) << Refusal(bmp);
  PutLittle32(bmp, 18, 10000);
  PutLittle32(bmp, 22, 10000);  // 10^8 pixels: each side is allowed, the area is not.
  EXPECT_NE(Refusal(bmp).find("declares 10000x10000 pixels"), std::string::npos) << Refusal(bmp);

  // A little-endian TIFF with one IFD at byte 8: ImageWidth 20000 (SHORT), ImageLength 10 (LONG).
  const std::vector<uint8_t> tiff = {'I', 'I', 42, 0, 8,  0, 0, 0, 2, 0, 0, 1, 3, 0, 1, 0, 0, 0, 0x20, 0x4E, 0, 0,
                                     1,   1,   4,  0, 1, 0, 0, 0, 10, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_NE(Refusal(tiff).find("the TIFF header declares 20000x10 pixels"), std::string::npos) << Refusal(tiff);
  // Kept from fuzzing: libtiff reads the first of two ImageLength tags (64501 rows, 264 MB).
  std::vector<uint8_t> twice = tiff;
  twice[8] = 3;
  twice.insert(twice.begin() + 34, {1, 1, 3, 0, 1, 0, 0, 0, 0xF5, 0xFB, 0, 0});
  EXPECT_NE(Refusal(twice).find("the TIFF has tag 257 twice"), std::string::npos) << Refusal(twice);
  std::vector<uint8_t> no_length(tiff.begin(), tiff.begin() + 22);
  no_length[8] = 1;  // One entry: no ImageLength.
  EXPECT_NE(Refusal(no_length).find("declares 20000x0"), std::string::npos) << Refusal(no_length);
}

// Kept from fuzzing: a 12090x12 TIFF in strips of 65535 rows; OpenCV allocates the strip as RGBA, 3.2 GB.
TEST(ImageHeader, BoundsTheTiffStripAndTileTheDecoderAllocates) {
  // Little endian, one IFD at byte 8 with three entries: ImageWidth 12090, ImageLength 12, RowsPerStrip.
  std::vector<uint8_t> tiff = {'I', 'I', 42, 0, 8, 0, 0, 0, 3, 0,                      //
                               0,   1,   3,  0, 1, 0, 0, 0, 0x3A, 0x2F, 0, 0,          // 256: 12090
                               1,   1,   3,  0, 1, 0, 0, 0, 12, 0, 0, 0,               // 257: 12
                               0x16, 1,  3,  0, 1, 0, 0, 0, 0xFF, 0xFF, 0, 0,          // 278: 65535
                               0,   0,   0,  0};
  EXPECT_NE(Refusal(tiff).find("the TIFF declares strips of 65535 rows of 12090 pixels"), std::string::npos)
      << Refusal(tiff);
  tiff[42] = 0x80;  // 384 rows a strip: 4.6 Mpx, as an image may be.
  tiff[43] = 0x01;
  EXPECT_EQ(ReadImageHeader(tiff, "strips.tif").width, 12090u);
  tiff[42] = tiff[43] = tiff[44] = tiff[45] = 0xFF;  // 2^32 - 1 (as LONG): one strip of the whole image.
  tiff[36] = 4;
  EXPECT_EQ(ReadImageHeader(tiff, "one_strip.tif").height, 12u);
  // The same entry as TileWidth, with no TileLength: a tile of no pixels.
  tiff[34] = 0x42;
  EXPECT_NE(Refusal(tiff).find("tiles of 4294967295x0 pixels"), std::string::npos) << Refusal(tiff);
}

// Kept from fuzzing: "BM", then a PNG's IHDR where the BMP header is: 2.3 GB asked of the decoder.
TEST(ImageHeader, AForgedBmpHeaderAsksNothing) {
  const std::vector<uint8_t> bytes = {0x42, 0x4d, 0x9f, 0xff, 0xda, 0x75, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00,
                                      0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x90, 0x00, 0x00,
                                      0x00, 0x0c, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                                      0x1e, 0x01, 0x1a, 0x37, 0x87, 0xa4, 0x0c, 0x10, 0x00, 0x00, 0x00};
  EXPECT_NE(Refusal(bytes).find("img: the BMP"), std::string::npos) << Refusal(bytes);
  EXPECT_THROW(DecodeGray8(bytes, "img"), InputError);
}

TEST(ImageHeader, UncompressedPixelsMustAllBeThere) {
  for (const std::string ext : {".bmp", ".pgm", ".ppm"}) {
    const std::vector<uint8_t> whole = Encoded(ext, ext == ".ppm" ? CV_8UC3 : CV_8UC1);
    EXPECT_EQ(Refusal(whole), "") << ext;
    const std::vector<uint8_t> cut(whole.begin(), whole.end() - 1);
    EXPECT_NE(Refusal(cut).find("truncated"), std::string::npos) << ext;
    EXPECT_NE(Refusal(cut).find("64x48 pixels need"), std::string::npos) << Refusal(cut);
  }
  // A top-down BMP (negative height) has the same rows.
  std::vector<uint8_t> top_down = Encoded(".bmp");
  PutLittle32(top_down, 22, static_cast<uint32_t>(-48));
  EXPECT_EQ(ReadImageHeader(top_down, "img").height, 48u);
}

TEST(ImageHeader, CutOffHeadersAreNamed) {
  const std::vector<uint8_t> jpg = Encoded(".jpg");
  const std::vector<uint8_t> cut(jpg.begin(), jpg.begin() + 30);
  EXPECT_NE(Refusal(cut).find("img: truncated JPEG header"), std::string::npos) << Refusal(cut);
  const std::vector<uint8_t> no_frame = {0xFF, 0xD8, 0xFF, 0xDA, 0, 2};
  EXPECT_NE(Refusal(no_frame).find("no frame header before its scan"), std::string::npos);
  EXPECT_NE(Refusal({'P', '5', ' ', '6', '4'}).find("truncated PNM header"), std::string::npos);
  EXPECT_NE(Refusal({'P', '5', ' ', '6', '4', ' ', 'x'}).find("has no height"), std::string::npos);
  EXPECT_NE(Refusal({'B', 'M', 0, 0}).find("truncated BMP header"), std::string::npos);
}

}  // namespace
}  // namespace dsm

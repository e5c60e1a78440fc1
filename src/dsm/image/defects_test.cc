// SPDX-License-Identifier: MIT
#include "dsm/image/defects.h"

#include <gtest/gtest.h>

#include "dsm/io/image_io.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

TEST(Defects, ParsesKindsAndRanges) {
  const std::vector<Defect> d = ParseDefects("black:200-214,noise:300-314,corrupt:350,cover:400-440");
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[0].kind, DefectKind::kBlack);
  EXPECT_EQ(d[0].first, 200);
  EXPECT_EQ(d[0].last, 214);
  EXPECT_EQ(d[2].kind, DefectKind::kCorrupt);
  EXPECT_EQ(d[2].first, 350);
  EXPECT_EQ(d[2].last, 350);
  EXPECT_EQ(d[3].kind, DefectKind::kCover);
  EXPECT_TRUE(ParseDefects("").empty());
  const std::vector<Defect> cut = ParseDefects("cut:10-19,black:25");
  ASSERT_EQ(cut.size(), 2u);
  EXPECT_EQ(cut[0].kind, DefectKind::kCut);
  EXPECT_FALSE(IsFileDefect(DefectKind::kCut));
  EXPECT_FALSE(IsCut(cut, 9));
  EXPECT_TRUE(IsCut(cut, 10));
  EXPECT_TRUE(IsCut(cut, 19));
  EXPECT_FALSE(IsCut(cut, 20));
  EXPECT_FALSE(IsCut(cut, 25));  // Black, not cut.
}

TEST(Defects, BadSpecsAreNamed) {
  for (const std::string spec : {"fog:3", "black", "black:5-2", "black:x", "noise:-4"}) {
    try {
      ParseDefects(spec);
      FAIL() << spec << " parsed";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--defects"), std::string::npos) << e.what();
    }
  }
}

TEST(Defects, ImageDefectsSpoilOnlyTheirFrames) {
  const std::vector<Defect> d = ParseDefects("black:2,saturated:3,noise:4,cover:5-12");
  Image<uint8_t> base(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) base(x, y) = static_cast<uint8_t>(100 + (x * 5 + y * 3) % 60);
  const auto mean = [](const Image<uint8_t>& im) {
    double s = 0;
    for (size_t i = 0; i < im.size(); ++i) s += im.data()[i];
    return s / im.size();
  };
  Image<uint8_t> im = base;
  ApplyImageDefects(d, 1, 1, &im);
  EXPECT_EQ(mean(im), mean(base));
  ApplyImageDefects(d, 2, 1, &im);
  EXPECT_EQ(mean(im), 0.0);
  im = base;
  ApplyImageDefects(d, 3, 1, &im);
  EXPECT_EQ(mean(im), 255.0);
  im = base;
  ApplyImageDefects(d, 4, 1, &im);
  EXPECT_NEAR(mean(im), 127.5, 5.0);
  im = base;
  ApplyImageDefects(d, 8, 1, &im);  // Mid-episode: dark, covered.
  EXPECT_LT(mean(im), 80.0);
}

TEST(Defects, FileDefectsDamageTheFile) {
  const auto dir = testing::ScratchDir("synth_defects");
  Image<uint8_t> im(64, 48);
  for (size_t i = 0; i < im.size(); ++i) im.data()[i] = static_cast<uint8_t>(i * 31 % 251);
  const std::vector<Defect> d = ParseDefects("corrupt:1,truncated:2,empty:3");
  for (int f = 0; f <= 3; ++f) {
    const auto path = dir / std::to_string(f) / "frame.png";
    std::filesystem::create_directories(path.parent_path());
    WriteGray8(path, im);
    ApplyFileDefects(d, f, path);
    if (f == 0) {
      EXPECT_EQ(ReadGray8(path).width(), 64);
    } else {
      EXPECT_THROW(ReadGray8(path), InputError) << f;
    }
  }
  EXPECT_EQ(std::filesystem::file_size(dir / "3" / "frame.png"), 0u);
}

}  // namespace
}  // namespace dsm

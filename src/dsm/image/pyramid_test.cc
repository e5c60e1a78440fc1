// SPDX-License-Identifier: MIT
#include "dsm/image/pyramid.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(ImagePyramid, LevelsAverageAndGradientsAreCentralDifferences) {
  Image<float> img(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) img(x, y) = 2.f * x + 3.f * y * y;
  const ImagePyramid pyr(img, 3);
  ASSERT_EQ(pyr.levels(), 3);
  EXPECT_EQ(pyr.width(2), 4);
  EXPECT_FLOAT_EQ(pyr.level(0)(5, 3)[1], 2.f);
  EXPECT_FLOAT_EQ(pyr.level(0)(5, 3)[2], 0.5f * 3.f * (16 - 4));
  // Level 1 pixel (2, 1) averages level-0 pixels x 4..5, y 2..3.
  EXPECT_FLOAT_EQ(pyr.level(1)(2, 1)[0], 0.25f * (8 + 10 + 8 + 10) + 0.25f * 3.f * (4 + 4 + 9 + 9));
  // Bilinear sample of a linear-in-x image is exact.
  EXPECT_NEAR(pyr.Sample(0, 5.25f, 3.f)[0], 2.f * 5.25f + 27.f, 1e-4);
}

}  // namespace
}  // namespace dsm

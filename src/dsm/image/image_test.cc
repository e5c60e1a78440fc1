// SPDX-License-Identifier: MIT
#include "dsm/image/image.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(Image, BilinearReproducesAffineFunctions) {
  Image<float> img(7, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) img(x, y) = 3.f * x - 2.f * y + 1.f;
  for (float x : {0.f, 0.25f, 2.5f, 5.9f})
    for (float y : {0.f, 1.75f, 3.99f}) EXPECT_NEAR(Bilinear(img, x, y), 3.f * x - 2.f * y + 1.f, 1e-5);
}

TEST(Image, InBoundsRespectsBorder) {
  Image<uint8_t> img(10, 8);
  EXPECT_TRUE(img.InBounds(0, 0));
  EXPECT_FALSE(img.InBounds(9.0, 3.0));  // needs x + 1 inside
  EXPECT_TRUE(img.InBounds(8.5, 6.5));
  EXPECT_FALSE(img.InBounds(1.0, 1.0, 2.0));
  EXPECT_TRUE(img.InBounds(2.0, 2.0, 2.0));
}

}  // namespace
}  // namespace dsm

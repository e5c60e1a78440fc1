// SPDX-License-Identifier: MIT
#include "dsm/image/signature.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dsm {
namespace {

ImagePyramid Stripes(float period, float contrast, float offset) {
  Image<float> image(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) image(x, y) = offset + contrast * std::sin(2.f * 3.14159f * (x + 0.5f * y) / period);
  return ImagePyramid(image, 3, false);
}

TEST(FrameSignature, TextureAndThumbnail) {
  const FrameSignature flat = ComputeSignature(ImagePyramid(Image<float>(64, 48, 0.f), 3, false));
  EXPECT_EQ(flat.texture, 0.0);
  EXPECT_TRUE(flat.thumbnail.empty());  // Nothing to compare.
  EXPECT_EQ(Similarity(flat, flat), -1.0);

  const FrameSignature a = ComputeSignature(Stripes(16.f, 40.f, 100.f));
  EXPECT_EQ(a.width, 16);
  EXPECT_EQ(a.height, 12);
  EXPECT_GT(a.texture, 5.0);
  EXPECT_NEAR(Similarity(a, a), 1.0, 1e-6);
  // Blind to brightness and contrast; not to a shift of half a period.
  EXPECT_NEAR(Similarity(a, ComputeSignature(Stripes(16.f, 20.f, 30.f))), 1.0, 1e-5);
  EXPECT_NEAR(ComputeSignature(Stripes(16.f, 20.f, 30.f)).texture, 0.5 * a.texture, 1e-3 * a.texture);
  EXPECT_LT(Similarity(a, ComputeSignature(Stripes(16.f, -40.f, 100.f))), -0.9);
}

TEST(FrameSignature, ImageBrightness) {
  // I_a = e^alpha I_b + beta exactly: the statistics give alpha and beta back.
  const FrameSignature b = ComputeSignature(Stripes(16.f, 40.f, 100.f));
  const FrameSignature a = ComputeSignature(Stripes(16.f, 20.f, 30.f));  // 0.5 * (I_b - 100) + 30
  double alpha = 0.0, beta = 0.0;
  ASSERT_TRUE(ImageBrightness(a, b, &alpha, &beta));
  EXPECT_NEAR(alpha, std::log(0.5), 1e-4);
  EXPECT_NEAR(beta, -20.0, 1e-2);
  EXPECT_NEAR(b.mean, 100.0, 1.0);
  const FrameSignature flat = ComputeSignature(ImagePyramid(Image<float>(64, 48, 7.f), 3, false));
  EXPECT_FALSE(ImageBrightness(a, flat, &alpha, &beta));
  EXPECT_FALSE(ImageBrightness(flat, a, &alpha, &beta));
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/image/pyramid.h"

#include <cmath>
#include <cstdint>
#include <random>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// An image of independent uniform grey levels in [0, 255).
Image<float> RandomImage(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> grey(0.f, 255.f);
  Image<float> img(width, height);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) img(x, y) = grey(rng);
  return img;
}

TEST(ImagePyramid, LevelsAverageAndGradientsAreCentralDifferences) {
  Image<float> img(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) img(x, y) = 2.f * x + 3.f * y * y;
  const ImagePyramid pyr(img, 3);
  ASSERT_EQ(pyr.levels(), 3);
  EXPECT_EQ(pyr.width(2), 4);
  EXPECT_FLOAT_EQ(pyr.At(0, 5, 3)[1], 2.f);
  EXPECT_FLOAT_EQ(pyr.At(0, 5, 3)[2], 0.5f * 3.f * (16 - 4));
  // Level 1 pixel (2, 1) averages level-0 pixels x 4..5, y 2..3.
  EXPECT_FLOAT_EQ(pyr.At(1, 2, 1)[0], 0.25f * (8 + 10 + 8 + 10) + 0.25f * 3.f * (4 + 4 + 9 + 9));
  // Bilinear sample of a linear-in-x image is exact.
  EXPECT_NEAR(pyr.Sample(0, 5.25f, 3.f)[0], 2.f * 5.25f + 27.f, 1e-4);
}

// Full pyramids hold 1/64 grey levels and 1/32 gradient steps; a frame's intensity-only pyramid
// keeps the floats, and WithGradients gives the same full pyramid as building it at once.
TEST(ImagePyramid, FixedPointGradientsRoundHalvesAwayFromZero) {
  // Level-0 gradients of a fixed-point image are multiples of 1/4 in gradient units (0.5 * 32 / 64
  // per unit step): a quarter of them are exact halves, of both signs. Each must round as
  // std::lround does, whatever the vectorised code does.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> grey(0, 255 * 64);
  const int w = 64, h = 16;
  Image<uint16_t> level0(w, h);
  for (size_t i = 0; i < level0.size(); ++i) level0.data()[i] = static_cast<uint16_t>(grey(rng));
  const ImagePyramid p = ImagePyramid::FromFixed(level0, 2);
  const auto v = [&](int x, int y) { return level0(x, y) / ImagePyramid::kValueScale; };
  const auto fixed = [](float g) { return std::lround(g * ImagePyramid::kGradientScale) / ImagePyramid::kGradientScale; };
  int halves = 0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const float gx = 0.5f * (v(x + 1, y) - v(x - 1, y)), gy = 0.5f * (v(x, y + 1) - v(x, y - 1));
      halves += std::abs(gx * ImagePyramid::kGradientScale - std::trunc(gx * ImagePyramid::kGradientScale)) == 0.5f;
      const PixelGrad g = p.At(0, x, y);
      ASSERT_FLOAT_EQ(g(0), v(x, y));
      ASSERT_EQ(g(1), fixed(gx)) << x << "," << y;
      ASSERT_EQ(g(2), fixed(gy)) << x << "," << y;
    }
  EXPECT_GT(halves, 100);
}

TEST(ImagePyramid, FixedPointFullPyramidAndIntensityOnlyFrames) {
  Image<float> img(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) img(x, y) = 100.f + 0.3f * x * x + std::sin(1.7f * y);
  const ImagePyramid full(img, 2);
  const ImagePyramid frame(img, 2, /*gradients=*/false);
  EXPECT_TRUE(full.HasGradients());
  EXPECT_FALSE(frame.HasGradients());
  EXPECT_EQ(frame.Value(0, 7, 3), img(7, 3));
  EXPECT_NEAR(full.Value(0, 7, 3), img(7, 3), 0.5f / 64.f);
  EXPECT_NEAR(full.At(0, 7, 3)[1], 0.5f * (img(8, 3) - img(6, 3)), 1.f / 64.f + 0.5f / 32.f);
  EXPECT_NEAR(frame.SampleValue(0, 7.5f, 3.25f), full.SampleValue(0, 7.5f, 3.25f), 1.f / 64.f);
  const ImagePyramid promoted = frame.WithGradients();
  for (int l = 0; l < 2; ++l)
    for (int y = 0; y < full.height(l); ++y)
      for (int x = 0; x < full.width(l); ++x) ASSERT_EQ(promoted.At(l, x, y), full.At(l, x, y));
  // Beyond the fixed-point range: clamped, not wrapped.
  Image<float> bright(4, 4, 2000.f);
  EXPECT_NEAR(ImagePyramid(bright, 1).Value(0, 1, 1), 65535.f / 64.f, 1e-3f);
}

// The eight-point sampler (vectorised where the CPU has AVX2) gives Sample's floats bit for bit,
// on every level, with negative gradients, up to the last pixel bilinear sampling may touch.
TEST(ImagePyramid, SampleEightIsSampleBitForBit) {
  const ImagePyramid pyr(RandomImage(96, 64, 11), 3);
  std::mt19937 rng(12);  // The sample points.
  for (int l = 0; l < pyr.levels(); ++l) {
    std::uniform_real_distribution<float> ux(0.f, pyr.width(l) - 1.001f), uy(0.f, pyr.height(l) - 1.001f);
    for (int round = 0; round < 50; ++round) {
      float x[8], y[8], value[8], dx[8], dy[8];
      for (int k = 0; k < 8; ++k) {
        x[k] = ux(rng);
        y[k] = uy(rng);
      }
      if (round == 0) {  // The corners: the first and the last pixels a sample may read.
        x[0] = y[0] = 0.f;
        x[1] = pyr.width(l) - 1.001f;
        y[1] = pyr.height(l) - 1.001f;
      }
      pyr.Sample8(l, x, y, value, dx, dy);
      for (int k = 0; k < 8; ++k) {
        const PixelGrad g = pyr.Sample(l, x[k], y[k]);
        EXPECT_EQ(value[k], g[0]);
        EXPECT_EQ(dx[k], g[1]);
        EXPECT_EQ(dy[k], g[2]);
      }
    }
  }
}

TEST(ImagePyramid, BSplineReproducesRampsAndDifferentiatesItsOwnValues) {
  // A linear ramp comes back exactly (value and gradient), wherever it is sampled.
  Image<float> ramp(64, 48);
  for (int y = 0; y < ramp.height(); ++y)
    for (int x = 0; x < ramp.width(); ++x) ramp(x, y) = 100.f + 1.5f * x - 0.75f * y;
  const ImagePyramid pyr(ramp, 1);
  for (const auto& [x, y] : {std::pair{10.f, 12.f}, {20.25f, 7.5f}, {33.9f, 30.1f}}) {
    const PixelGrad g = pyr.SampleBSpline(0, x, y);
    EXPECT_NEAR(g[0], 100.f + 1.5f * x - 0.75f * y, 1e-3f);
    EXPECT_NEAR(g[1], 1.5f, 1e-4f);
    EXPECT_NEAR(g[2], -0.75f, 1e-4f);
  }
  // On noise, the gradient is the derivative of the values (central differences of samples).
  const ImagePyramid noisy(RandomImage(64, 48, 5), 1);
  const float h = 1e-2f;
  for (const auto& [x, y] : {std::pair{10.3f, 12.6f}, {20.7f, 7.2f}, {33.5f, 30.5f}}) {
    const PixelGrad g = noisy.SampleBSpline(0, x, y);
    const float dx = (noisy.SampleBSpline(0, x + h, y)[0] - noisy.SampleBSpline(0, x - h, y)[0]) / (2.f * h);
    const float dy = (noisy.SampleBSpline(0, x, y + h)[0] - noisy.SampleBSpline(0, x, y - h)[0]) / (2.f * h);
    EXPECT_NEAR(g[1], dx, 0.05f);
    EXPECT_NEAR(g[2], dy, 0.05f);
  }
}

TEST(ImagePyramid, BSplineAveragesNoiseAlikeAtEveryPosition) {
  // The variance of interpolated white noise, at a pixel and half-way between four: bilinear
  // interpolation divides it by 4 between the two, the B-spline by less than 1.25.
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0.f, 5.f);
  Image<float> img(256, 256);
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) img(x, y) = 500.f + noise(rng);
  const ImagePyramid pyr(img, 1);
  const auto variance = [&](float offset, bool bspline) {
    double sum = 0.0, sum_sq = 0.0;
    int n = 0;
    for (int y = 4; y < 250; y += 2)
      for (int x = 4; x < 250; x += 2) {
        const float v = bspline ? pyr.SampleBSpline(0, x + offset, y + offset)[0] : pyr.SampleValue(0, x + offset, y + offset);
        sum += v;
        sum_sq += v * v;
        ++n;
      }
    return sum_sq / n - (sum / n) * (sum / n);
  };
  const double bilinear_ratio = variance(0.f, false) / variance(0.5f, false);
  const double bspline_ratio = variance(0.f, true) / variance(0.5f, true);
  EXPECT_GT(bilinear_ratio, 3.4);
  EXPECT_LT(bilinear_ratio, 4.6);
  EXPECT_GT(bspline_ratio, 1.0);
  EXPECT_LT(bspline_ratio, 1.3);  // Expected 0.25 / 0.212 = 1.18.
}

}  // namespace
}  // namespace dsm

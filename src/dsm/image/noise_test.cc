// SPDX-License-Identifier: MIT
#include "dsm/image/noise.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace dsm {
namespace {

// Smooth shading (a linear ramp and a gentle bump) with Gaussian noise of `sigma` added.
Image<float> NoisyShading(int w, int h, double sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, static_cast<float>(sigma));
  Image<float> img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(x, y) = 60.f + 0.2f * x + 0.1f * y + 30.f * std::sin(0.02f * x) * std::cos(0.03f * y) + noise(rng);
  return img;
}

TEST(ImageNoise, EstimatesTheNoiseSigmaOfShadedImages) {
  EXPECT_LT(EstimateNoiseSigma(NoisyShading(320, 240, 0.0, 1)), 0.05f);
  for (double sigma : {1.0, 4.0}) {
    EXPECT_NEAR(EstimateNoiseSigma(NoisyShading(320, 240, sigma, 2)), sigma, 0.06 * sigma) << sigma;
  }
}

// Edges are few per block: the median ignores them.
TEST(ImageNoise, BlockMedianIgnoresAFewEdges) {
  Image<float> img = NoisyShading(128, 128, 2.0, 3);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if (x % 16 == 0) img(x, y) += 80.f;  // A step edge every 16 pixels.
  EXPECT_NEAR(EstimateNoiseSigma(img), 2.0, 0.4);
}

}  // namespace
}  // namespace dsm

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

TEST(ImageNoise, GaussianSmoothingKeepsLinearShadingAndLowersNoise) {
  Image<float> ramp(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) ramp(x, y) = 10.f + 2.f * x - 1.5f * y;
  const Image<float> smooth = GaussianSmooth(ramp, 0.7f);
  // A normalised symmetric kernel leaves linear intensity exact away from the border ...
  EXPECT_NEAR(smooth(20, 15), ramp(20, 15), 1e-4);
  EXPECT_NEAR(smooth(5, 25), ramp(5, 25), 1e-4);
  // ... and pulls the border pixel towards its repeated neighbours (only the inside is ramped).
  EXPECT_GT(smooth(0, 15), ramp(0, 15));
  const Image<float> copy = GaussianSmooth(ramp, 0.f);
  EXPECT_EQ(copy(7, 7), ramp(7, 7));

  // Independent noise: its standard deviation after a 1-D kernel k is |k| s; in 2-D |k|^2 s
  // (0.7 px: |k|^2 = 0.40).
  const float sigma = 0.7f;
  double k2 = 0.0, sum = 0.0;
  for (int i = -3; i <= 3; ++i) sum += std::exp(-0.5 * i * i / (sigma * sigma));
  for (int i = -3; i <= 3; ++i) k2 += std::pow(std::exp(-0.5 * i * i / (sigma * sigma)) / sum, 2);
  const Image<float> noisy = NoisyShading(320, 240, 5.0, 4);
  const Image<float> denoised = GaussianSmooth(noisy, sigma);
  const Image<float> clean = GaussianSmooth(NoisyShading(320, 240, 0.0, 4), sigma);
  double sq = 0.0;
  int n = 0;
  for (int y = 10; y < 230; ++y)
    for (int x = 10; x < 310; ++x, ++n) sq += std::pow(denoised(x, y) - clean(x, y), 2);
  EXPECT_NEAR(std::sqrt(sq / n), k2 * 5.0, 0.03 * k2 * 5.0);
}

// After smoothing, the noise level estimated from the image times the gain predicts the noise of
// a central-difference gradient, as sigma / sqrt(2) does on the raw image.
TEST(ImageNoise, GainPredictsTheGradientNoiseOfSmoothedImages) {
  EXPECT_EQ(SmoothedGradientNoiseGain(0.f), 1.0);
  for (float sigma : {0.f, 0.7f, 1.2f}) {
    const Image<float> noisy = GaussianSmooth(NoisyShading(320, 240, 6.0, 5), sigma);
    const Image<float> clean = GaussianSmooth(NoisyShading(320, 240, 0.0, 5), sigma);
    double sq = 0.0;
    int n = 0;
    for (int y = 10; y < 230; ++y)
      for (int x = 10; x < 310; ++x, ++n) {
        const double g = 0.5 * ((noisy(x + 1, y) - noisy(x - 1, y)) - (clean(x + 1, y) - clean(x - 1, y)));
        sq += g * g;
      }
    const double predicted = SmoothedGradientNoiseGain(sigma) * EstimateNoiseSigma(noisy) / std::sqrt(2.0);
    EXPECT_NEAR(predicted, std::sqrt(sq / n), 0.08 * std::sqrt(sq / n)) << sigma;
  }
  EXPECT_NEAR(SmoothedGradientNoiseGain(0.7f), 3.48, 0.01);
}

}  // namespace
}  // namespace dsm

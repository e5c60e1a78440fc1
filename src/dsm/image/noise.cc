// SPDX-License-Identifier: MIT
#include "dsm/image/noise.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

#include "dsm/util/median.h"

namespace dsm {
namespace {

// |N * I| at (x, y), 1 <= x < width - 1, 1 <= y < height - 1.
float NoiseResponse(const Image<float>& I, int x, int y) {
  const float* a = I.Row(y - 1) + x;
  const float* b = I.Row(y) + x;
  const float* c = I.Row(y + 1) + x;
  return std::abs(a[-1] - 2.f * a[0] + a[1] - 2.f * b[-1] + 4.f * b[0] - 2.f * b[1] + c[-1] - 2.f * c[0] + c[1]);
}

}  // namespace

float BlockNoiseSigma(const Image<float>& image, int bx, int by) {
  const int w = image.width(), h = image.height();
  std::vector<float> n;
  n.reserve(kNoiseBlock * kNoiseBlock);
  for (int y = std::max(1, by * kNoiseBlock); y < std::min(h - 1, (by + 1) * kNoiseBlock); ++y)
    for (int x = std::max(1, bx * kNoiseBlock); x < std::min(w - 1, (bx + 1) * kNoiseBlock); ++x)
      n.push_back(NoiseResponse(image, x, y));
  return n.empty() ? 0.f : Median(n) / (6.f * 0.6745f);
}

float EstimateNoiseSigma(const Image<float>& image) {
  const int bw = (image.width() + kNoiseBlock - 1) / kNoiseBlock, bh = (image.height() + kNoiseBlock - 1) / kNoiseBlock;
  std::vector<float> sigmas(static_cast<size_t>(bw) * bh);
  tbb::parallel_for(0, bh, [&](int by) {
    for (int bx = 0; bx < bw; ++bx) sigmas[static_cast<size_t>(by) * bw + bx] = BlockNoiseSigma(image, bx, by);
  });
  return sigmas.empty() ? 0.f : Median(sigmas);
}

}  // namespace dsm

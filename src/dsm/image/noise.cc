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

// The normalised 1-D Gaussian of `sigma` pixels, truncated at 3 sigma (at least 3 taps).
std::vector<float> GaussianKernel(float sigma) {
  const int r = std::max(1, static_cast<int>(std::ceil(3.f * sigma)));
  std::vector<float> k(2 * r + 1);
  float sum = 0.f;
  for (int i = -r; i <= r; ++i) sum += k[i + r] = std::exp(-0.5f * i * i / (sigma * sigma));
  for (float& v : k) v /= sum;
  return k;
}

// The full 2-D convolution of a (ha x wa, row-major) with b (hb x wb).
std::vector<double> Convolve2d(const std::vector<double>& a, int ha, int wa, const std::vector<double>& b, int hb,
                               int wb) {
  const int h = ha + hb - 1, w = wa + wb - 1;
  std::vector<double> out(static_cast<size_t>(h) * w, 0.0);
  for (int i = 0; i < ha; ++i)
    for (int j = 0; j < wa; ++j)
      for (int p = 0; p < hb; ++p)
        for (int q = 0; q < wb; ++q) out[(i + p) * w + (j + q)] += a[i * wa + j] * b[p * wb + q];
  return out;
}

double Norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
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

Image<float> GaussianSmooth(const Image<float>& image, float sigma) {
  if (!(sigma > 0.f)) return image;
  const std::vector<float> k = GaussianKernel(sigma);
  const int r = static_cast<int>(k.size() / 2);
  const int w = image.width(), h = image.height();
  // Rows, then columns; a pixel beyond the border takes the border pixel's value.
  Image<float> rows(w, h), out(w, h);
  tbb::parallel_for(0, h, [&](int y) {
    const float* in = image.Row(y);
    float* o = rows.Row(y);
    for (int x = 0; x < w; ++x) {
      float acc = 0.f;
      for (int i = -r; i <= r; ++i) acc += k[i + r] * in[std::clamp(x + i, 0, w - 1)];
      o[x] = acc;
    }
  });
  tbb::parallel_for(0, h, [&](int y) {
    float* o = out.Row(y);
    for (int x = 0; x < w; ++x) o[x] = 0.f;
    for (int i = -r; i <= r; ++i) {
      const float* in = rows.Row(std::clamp(y + i, 0, h - 1));
      const float ki = k[i + r];
      for (int x = 0; x < w; ++x) o[x] += ki * in[x];
    }
  });
  return out;
}

namespace {

// The 2-D kernel of the Gaussian of `sigma` (n x n, row-major) and |N * G| / 6, the noise level
// the estimate above reports for unit noise smoothed by it.
struct SmoothedUnitNoise {
  std::vector<double> g;
  int n = 0;
  double estimate = 0.0;
};
SmoothedUnitNoise SmoothedUnitNoiseOf(float sigma) {
  const std::vector<float> k = GaussianKernel(sigma);
  SmoothedUnitNoise u;
  u.n = static_cast<int>(k.size());
  u.g.resize(static_cast<size_t>(u.n) * u.n);
  for (int i = 0; i < u.n; ++i)
    for (int j = 0; j < u.n; ++j) u.g[i * u.n + j] = double(k[i]) * k[j];
  const std::vector<double> N = {1, -2, 1, -2, 4, -2, 1, -2, 1};
  u.estimate = Norm(Convolve2d(u.g, u.n, u.n, N, 3, 3)) / 6.0;
  return u;
}

}  // namespace

double SmoothedGradientNoiseGain(float sigma) {
  if (!(sigma > 0.f)) return 1.0;
  const SmoothedUnitNoise u = SmoothedUnitNoiseOf(sigma);
  const std::vector<double> d = {0.5, 0.0, -0.5};
  return Norm(Convolve2d(u.g, u.n, u.n, d, 1, 3)) / (u.estimate / std::sqrt(2.0));
}

double SmoothedValueNoiseGain(float sigma) {
  if (!(sigma > 0.f)) return 1.0;
  const SmoothedUnitNoise u = SmoothedUnitNoiseOf(sigma);
  return Norm(u.g) / u.estimate;
}

}  // namespace dsm

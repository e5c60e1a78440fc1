// SPDX-License-Identifier: MIT
#include "dsm/image/signature.h"

#include <algorithm>
#include <cmath>

namespace dsm {

namespace {

double MeanGradient(const ImagePyramid& pyramid, int l) {
  const int w = pyramid.width(l), h = pyramid.height(l);
  if (w < 3 || h < 3) return 0.0;
  double sum = 0.0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const float dx = pyramid.Value(l, x + 1, y) - pyramid.Value(l, x - 1, y);
      const float dy = pyramid.Value(l, x, y + 1) - pyramid.Value(l, x, y - 1);
      sum += 0.5 * (std::abs(dx) + std::abs(dy));
    }
  return sum / ((w - 2.0) * (h - 2.0));
}

}  // namespace

FrameSignature ComputeSignature(const ImagePyramid& pyramid) {
  FrameSignature s;
  s.texture = MeanGradient(pyramid, std::min(1, pyramid.levels() - 1));
  const int l = pyramid.levels() - 1, w = pyramid.width(l), h = pyramid.height(l);
  // 3 x 3 binomial (1 2 1)^T (1 2 1) / 16, the border replicated.
  const auto at = [&](int x, int y) {
    return pyramid.Value(l, std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1));
  };
  std::vector<float> t(static_cast<size_t>(w) * h);
  double mean = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v = 0.f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) v += (2 - std::abs(dx)) * (2 - std::abs(dy)) * at(x + dx, y + dy);
      t[y * w + x] = v / 16.f;
      mean += v / 16.f;
    }
  mean /= t.size();
  double norm = 0.0;
  for (float& v : t) {
    v -= static_cast<float>(mean);
    norm += static_cast<double>(v) * v;
  }
  s.width = w;
  s.height = h;
  s.mean = mean;
  s.deviation = std::sqrt(norm / t.size());
  if (norm < 1e-6 * t.size()) return s;  // Uniform: nothing to compare.
  const float scale = static_cast<float>(1.0 / std::sqrt(norm));
  for (float& v : t) v *= scale;
  s.thumbnail = std::move(t);
  return s;
}

double Similarity(const FrameSignature& a, const FrameSignature& b) {
  if (a.thumbnail.empty() || a.thumbnail.size() != b.thumbnail.size() || a.width != b.width) return -1.0;
  double dot = 0.0;
  for (size_t i = 0; i < a.thumbnail.size(); ++i) dot += static_cast<double>(a.thumbnail[i]) * b.thumbnail[i];
  return dot;
}

bool ImageBrightness(const FrameSignature& a, const FrameSignature& b, double* alpha, double* beta) {
  if (a.thumbnail.empty() || b.thumbnail.empty()) return false;
  *alpha = std::log(a.deviation / b.deviation);
  *beta = a.mean - std::exp(*alpha) * b.mean;
  return true;
}

}  // namespace dsm

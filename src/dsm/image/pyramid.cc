// SPDX-License-Identifier: MIT
#include "dsm/image/pyramid.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace dsm {

namespace {

// Level l+1: the mean of each 2 x 2 block of level l.
Image<float> Half(const Image<float>& current) {
  Image<float> half(current.width() / 2, current.height() / 2);
  for (int y = 0; y < half.height(); ++y) {
    const float* r0 = current.Row(2 * y);
    const float* r1 = current.Row(2 * y + 1);
    float* out = half.Row(y);
    for (int x = 0; x < half.width(); ++x) out[x] = 0.25f * (r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1]);
  }
  return half;
}

// Round half away from zero, as std::lround, in operations that vectorise: truncation toward
// zero, then one step away from zero when the dropped part is at least a half. The dropped part
// v - trunc(v) is exact in float (|v| < 2^31 here; Sterbenz: trunc(v) is within a factor 2 of v).
inline int RoundHalfAway(float v) {
  const int t = static_cast<int>(v);
  const float d = v - static_cast<float>(t);
  return t + (d >= 0.5f) - (d <= -0.5f);
}
inline uint16_t ToFixedValue(float v) {
  return static_cast<uint16_t>(RoundHalfAway(std::min(std::max(v * ImagePyramid::kValueScale, 0.f), 65535.f)));
}
inline int16_t ToFixedGradient(float g) {
  return static_cast<int16_t>(RoundHalfAway(std::min(std::max(g * ImagePyramid::kGradientScale, -32767.f), 32767.f)));
}

// (I, dI/dx, dI/dy) in fixed point, central differences (one-sided at the border). Rows in
// parallel (each pixel on its own: the result does not depend on the split); within a row the
// three channels are computed in separate arrays (vectorised), then interleaved.
Image<PixelFixed> FixedWithGradients(const Image<float>& img) {
  const int w = img.width(), h = img.height();
  Image<PixelFixed> out(w, h, PixelFixed{0, 0, 0});
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    std::vector<uint16_t> value(w);
    std::vector<int16_t> dx(w), dy(w);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const float* r = img.Row(y);
      const float* up = img.Row(y > 0 ? y - 1 : y);
      const float* down = img.Row(y < h - 1 ? y + 1 : y);
      const float sy = (y > 0 && y < h - 1) ? 0.5f : 1.f;
      for (int x = 0; x < w; ++x) {
        value[x] = ToFixedValue(r[x]);
        dy[x] = ToFixedGradient(sy * (down[x] - up[x]));
      }
      for (int x = 1; x < w - 1; ++x) dx[x] = ToFixedGradient(0.5f * (r[x + 1] - r[x - 1]));
      dx[0] = ToFixedGradient(r[std::min(1, w - 1)] - r[0]);
      if (w > 1) dx[w - 1] = ToFixedGradient(r[w - 1] - r[w - 2]);
      PixelFixed* o = out.Row(y);
      for (int x = 0; x < w; ++x) o[x] = {value[x], dx[x], dy[x]};
    }
  });
  return out;
}

}  // namespace

ImagePyramid::ImagePyramid(Image<float> image, int levels, bool gradients) {
  DSM_CHECK(levels >= 1, "a pyramid needs at least one level");
  const int div = 1 << (levels - 1);
  DSM_CHECK(image.width() % div == 0 && image.height() % div == 0, "image size must divide by 2^(levels-1)");
  values_.reserve(levels);
  values_.push_back(std::move(image));
  for (int l = 1; l < levels; ++l) values_.push_back(Half(values_.back()));
  if (gradients) *this = WithGradients();
}

ImagePyramid ImagePyramid::FromFixed(const Image<uint16_t>& level0, int levels) {
  // Every level from the fixed-point level 0 (exact in float), so that a rebuild is the original.
  Image<float> current(level0.width(), level0.height());
  for (size_t i = 0; i < level0.size(); ++i) current.data()[i] = level0.data()[i] * (1.f / kValueScale);
  ImagePyramid out;
  for (int l = 0; l < levels; ++l) {
    out.fixed_.push_back(FixedWithGradients(current));
    if (l + 1 < levels) current = Half(current);
  }
  return out;
}

ImagePyramid ImagePyramid::WithGradients() const {
  if (HasGradients()) return *this;
  const Image<float>& v = values_[0];
  Image<uint16_t> level0(v.width(), v.height());
  for (size_t i = 0; i < v.size(); ++i) level0.data()[i] = ToFixedValue(v.data()[i]);
  return FromFixed(level0, levels());
}

Image<float> ImagePyramid::ValuesLevel0() const {
  if (!HasGradients()) return values_[0];
  const Image<PixelFixed>& l0 = fixed_[0];
  Image<float> out(l0.width(), l0.height());
  for (size_t i = 0; i < l0.size(); ++i) out.data()[i] = l0.data()[i].value * (1.f / kValueScale);
  return out;
}

Image<uint16_t> ImagePyramid::FixedLevel0() const {
  const Image<PixelFixed>& l0 = fixed_[0];
  Image<uint16_t> out(l0.width(), l0.height());
  for (size_t i = 0; i < l0.size(); ++i) out.data()[i] = l0.data()[i].value;
  return out;
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/image/pyramid.h"

#include <algorithm>
#include <cmath>
#include <utility>

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

// Round half away from zero, as std::lround, inline: a float plus or minus 0.5 is exact in double,
// and the conversion truncates toward zero.
inline int RoundHalfAway(float v) { return static_cast<int>(static_cast<double>(v) + (v < 0.f ? -0.5 : 0.5)); }
uint16_t ToFixedValue(float v) {
  return static_cast<uint16_t>(RoundHalfAway(std::clamp(v * ImagePyramid::kValueScale, 0.f, 65535.f)));
}
int16_t ToFixedGradient(float g) {
  return static_cast<int16_t>(RoundHalfAway(std::clamp(g * ImagePyramid::kGradientScale, -32767.f, 32767.f)));
}

// (I, dI/dx, dI/dy) in fixed point, central differences (one-sided at the border). Rows in
// parallel (each pixel on its own: the result does not depend on the split).
Image<PixelFixed> FixedWithGradients(const Image<float>& img) {
  const int w = img.width(), h = img.height();
  Image<PixelFixed> out(w, h, PixelFixed{0, 0, 0});
  tbb::parallel_for(0, h, [&](int y) {
    const float* r = img.Row(y);
    const float* up = img.Row(y > 0 ? y - 1 : y);
    const float* down = img.Row(y < h - 1 ? y + 1 : y);
    const float sy = (y > 0 && y < h - 1) ? 0.5f : 1.f;
    PixelFixed* o = out.Row(y);
    const auto pixel = [&](int x, int xl, int xr, float sx) {
      o[x] = {ToFixedValue(r[x]), ToFixedGradient(sx * (r[xr] - r[xl])), ToFixedGradient(sy * (down[x] - up[x]))};
    };
    pixel(0, 0, std::min(1, w - 1), 1.f);
    for (int x = 1; x < w - 1; ++x) pixel(x, x - 1, x + 1, 0.5f);
    if (w > 1) pixel(w - 1, w - 2, w - 1, 1.f);
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

Image<uint16_t> ImagePyramid::FixedLevel0() const {
  const Image<PixelFixed>& l0 = fixed_[0];
  Image<uint16_t> out(l0.width(), l0.height());
  for (size_t i = 0; i < l0.size(); ++i) out.data()[i] = l0.data()[i].value;
  return out;
}

}  // namespace dsm

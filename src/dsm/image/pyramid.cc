// SPDX-License-Identifier: MIT
#include "dsm/image/pyramid.h"

namespace dsm {

namespace {

Image<PixelGrad> WithGradients(const Image<float>& img) {
  const int w = img.width(), h = img.height();
  Image<PixelGrad> out(w, h, PixelGrad::Zero());
  for (int y = 0; y < h; ++y) {
    const float* r = img.Row(y);
    const float* up = img.Row(y > 0 ? y - 1 : y);
    const float* down = img.Row(y < h - 1 ? y + 1 : y);
    const float sy = (y > 0 && y < h - 1) ? 0.5f : 1.f;
    for (int x = 0; x < w; ++x) {
      const int xl = x > 0 ? x - 1 : x, xr = x < w - 1 ? x + 1 : x;
      const float sx = (x > 0 && x < w - 1) ? 0.5f : 1.f;
      out(x, y) = PixelGrad(r[x], sx * (r[xr] - r[xl]), sy * (down[x] - up[x]));
    }
  }
  return out;
}

}  // namespace

ImagePyramid::ImagePyramid(const Image<float>& image, int levels) {
  DSM_CHECK(levels >= 1, "a pyramid needs at least one level");
  const int div = 1 << (levels - 1);
  DSM_CHECK(image.width() % div == 0 && image.height() % div == 0, "image size must divide by 2^(levels-1)");
  Image<float> current = image;
  for (int l = 0; l < levels; ++l) {
    levels_.push_back(WithGradients(current));
    if (l + 1 == levels) break;
    Image<float> half(current.width() / 2, current.height() / 2);
    for (int y = 0; y < half.height(); ++y) {
      const float* r0 = current.Row(2 * y);
      const float* r1 = current.Row(2 * y + 1);
      float* out = half.Row(y);
      for (int x = 0; x < half.width(); ++x) out[x] = 0.25f * (r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1]);
    }
    current = std::move(half);
  }
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
// Image pyramid with gradients, the data every photometric residual samples.
//
// Level 0 is the undistorted image; level l+1 averages 2 x 2 blocks of level l. Each pixel stores
// (I, dI/dx, dI/dy) with central differences (one-sided at the border). A pinhole camera at
// level l has f_l = f / 2^l and c_l = (c + 0.5) / 2^l - 0.5 (pixel centres at integers).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "dsm/image/image.h"

namespace dsm {

using PixelGrad = Eigen::Vector3f;  // (I, dI/dx, dI/dy)

class ImagePyramid {
 public:
  ImagePyramid() = default;
  // `image` must have width and height divisible by 2^(levels - 1) (checked).
  ImagePyramid(const Image<float>& image, int levels);

  int levels() const { return static_cast<int>(levels_.size()); }
  const Image<PixelGrad>& level(int l) const { return levels_[l]; }
  int width(int l) const { return levels_[l].width(); }
  int height(int l) const { return levels_[l].height(); }

  // Bilinear (I, dI/dx, dI/dy) at (x, y) of level l; the caller guarantees InBounds(x, y).
  PixelGrad Sample(int l, float x, float y) const {
    const Image<PixelGrad>& img = levels_[l];
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    const float fx = x - ix, fy = y - iy;
    const PixelGrad* p = img.Row(iy) + ix;
    const int w = img.width();
    return (1.f - fy) * ((1.f - fx) * p[0] + fx * p[1]) + fy * ((1.f - fx) * p[w] + fx * p[w + 1]);
  }
  float SampleValue(int l, float x, float y) const {
    const Image<PixelGrad>& img = levels_[l];
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    const float fx = x - ix, fy = y - iy;
    const PixelGrad* p = img.Row(iy) + ix;
    const int w = img.width();
    return (1.f - fy) * ((1.f - fx) * p[0][0] + fx * p[1][0]) + fy * ((1.f - fx) * p[w][0] + fx * p[w + 1][0]);
  }
  bool InBounds(int l, float x, float y, float border) const { return levels_[l].InBounds(x, y, border); }

  // Asks the cache for the pixels within `radius` (+1 for bilinear) of (x, y) at level l, ahead of
  // sampling them: residuals over many keyframes read images far larger than the caches, and the
  // loads, not the arithmetic, dominate. Does nothing outside the image.
  void Prefetch(int l, int x, int y, int radius) const {
    const Image<PixelGrad>& img = levels_[l];
    if (x - radius < 0 || y - radius < 0 || x + radius + 1 >= img.width() || y + radius + 1 >= img.height()) return;
    for (int r = y - radius; r <= y + radius + 1; ++r) {
      const auto first = reinterpret_cast<uintptr_t>(img.Row(r) + x - radius) & ~uintptr_t{63};
      const auto last = reinterpret_cast<uintptr_t>(img.Row(r) + x + radius + 2) - 1;
      for (uintptr_t line = first; line <= last; line += 64) __builtin_prefetch(reinterpret_cast<const void*>(line));
    }
  }

 private:
  std::vector<Image<PixelGrad>> levels_;
};

}  // namespace dsm

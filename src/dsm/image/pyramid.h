// SPDX-License-Identifier: MIT
// Image pyramid with gradients, the data every photometric residual samples.
//
// Level 0 is the undistorted image; level l+1 averages 2 x 2 blocks of level l. Each pixel stores
// (I, dI/dx, dI/dy) with central differences (one-sided at the border). A pinhole camera at
// level l has f_l = f / 2^l and c_l = (c + 0.5) / 2^l - 0.5 (pixel centres at integers).
#pragma once

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

 private:
  std::vector<Image<PixelGrad>> levels_;
};

}  // namespace dsm

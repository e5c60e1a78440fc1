// SPDX-License-Identifier: MIT
// Image pyramid with gradients, the data every photometric residual samples.
//
// Level 0 is the undistorted image; level l+1 averages 2 x 2 blocks of level l. A pinhole camera
// at level l has f_l = f / 2^l and c_l = (c + 0.5) / 2^l - 0.5 (pixel centres at integers).
//
// A full pyramid (a keyframe's) stores per pixel (I, dI/dx, dI/dy), gradients by central
// differences (one-sided at the border), interleaved (a residual samples all three at once) and
// in fixed point: I in 1/64 grey level (0..1023.98), the gradients in 1/32 (+-1023.97), 6 bytes
// instead of 12. The quantisation is far below image noise; it halves the memory every residual
// of the bundle adjustment reads, and the pyramid is a function of its 16-bit level 0 alone, so
// a keyframe can drop it and rebuild it exactly (FromFixed).
//
// A frame that is only tracked needs no gradients: frame tracking is inverse compositional (the
// reference keyframe's gradients) and the candidates' epipolar search differentiates the
// interpolated intensities, which away from the border equals interpolating the central
// differences. Its pyramid holds float intensities alone; a keyframe's gets the rest
// (WithGradients).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "dsm/image/image.h"

namespace dsm {

using PixelGrad = Eigen::Vector3f;  // (I, dI/dx, dI/dy)

// A pixel of a full pyramid in fixed point (see above).
struct PixelFixed {
  uint16_t value;
  int16_t dx, dy;
};

class ImagePyramid {
 public:
  static constexpr float kValueScale = 64.f;     // Fixed-point units per grey level.
  static constexpr float kGradientScale = 32.f;

  ImagePyramid() = default;
  // `image` must have width and height divisible by 2^(levels - 1) (checked).
  ImagePyramid(Image<float> image, int levels, bool gradients = true);
  // The full pyramid whose level 0 is `level0` (1/kValueScale grey levels).
  static ImagePyramid FromFixed(const Image<uint16_t>& level0, int levels);

  // This pyramid with the gradients (a copy when it has them already).
  ImagePyramid WithGradients() const;
  bool HasGradients() const { return !fixed_.empty(); }
  // Level 0 of a full pyramid in fixed point (what FromFixed takes).
  Image<uint16_t> FixedLevel0() const;

  // Level 0's intensities (grey levels), whether or not the pyramid has gradients.
  Image<float> ValuesLevel0() const;
  int levels() const { return static_cast<int>(HasGradients() ? fixed_.size() : values_.size()); }
  int width(int l) const { return HasGradients() ? fixed_[l].width() : values_[l].width(); }
  int height(int l) const { return HasGradients() ? fixed_[l].height() : values_[l].height(); }
  float Value(int l, int x, int y) const {
    return HasGradients() ? fixed_[l](x, y).value * (1.f / kValueScale) : values_[l](x, y);
  }
  // (I, dI/dx, dI/dy) at a pixel; needs HasGradients().
  PixelGrad At(int l, int x, int y) const {
    const PixelFixed& p = fixed_[l](x, y);
    return PixelGrad(p.value * (1.f / kValueScale), p.dx * (1.f / kGradientScale), p.dy * (1.f / kGradientScale));
  }

  // Bilinear (I, dI/dx, dI/dy) at (x, y) of level l; needs HasGradients() and InBounds(x, y).
  PixelGrad Sample(int l, float x, float y) const {
    const Image<PixelFixed>& img = fixed_[l];
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    const float fx = x - ix, fy = y - iy;
    const PixelFixed* p = img.Row(iy) + ix;
    const PixelFixed* q = p + img.width();
    const float w00 = (1.f - fx) * (1.f - fy), w10 = fx * (1.f - fy), w01 = (1.f - fx) * fy, w11 = fx * fy;
    const float v = w00 * p[0].value + w10 * p[1].value + w01 * q[0].value + w11 * q[1].value;
    const float dx = w00 * p[0].dx + w10 * p[1].dx + w01 * q[0].dx + w11 * q[1].dx;
    const float dy = w00 * p[0].dy + w10 * p[1].dy + w01 * q[0].dy + w11 * q[1].dy;
    return PixelGrad(v * (1.f / kValueScale), dx * (1.f / kGradientScale), dy * (1.f / kGradientScale));
  }
  // The cubic B-spline approximation at (x, y) of level l and its derivatives:
  //   I(x, y) = sum_ij B(x - i) B(y - j) I_ij
  // over the 4 x 4 pixels around (x, y), B the cubic B-spline (pyramid_sample.cc). It reproduces
  // linear ramps exactly and blurs like a Gaussian of 0.58 px; unlike bilinear interpolation it
  // averages independent pixel noise by nearly the same factor at every position: the squared
  // weights sum to 0.25 at a pixel and 0.21 half-way (bilinear: 1 and 0.25). Needs
  // HasGradients() and InBounds(x, y, 2).
  PixelGrad SampleBSpline(int l, float x, float y) const;
  // Sample at eight points (x[k], y[k]) into value, dx, dy (8 floats each): bit for bit what
  // Sample gives, vectorised (pyramid_sample.cc); needs HasGradients() and every point InBounds.
  void Sample8(int l, const float* x, const float* y, float* value, float* dx, float* dy) const;
  float SampleValue(int l, float x, float y) const {
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    const float fx = x - ix, fy = y - iy;
    if (HasGradients()) {
      const PixelFixed* p = fixed_[l].Row(iy) + ix;
      const PixelFixed* q = p + fixed_[l].width();
      return ((1.f - fy) * ((1.f - fx) * p[0].value + fx * p[1].value) +
              fy * ((1.f - fx) * q[0].value + fx * q[1].value)) *
             (1.f / kValueScale);
    }
    const float* p = values_[l].Row(iy) + ix;
    const int w = values_[l].width();
    return (1.f - fy) * ((1.f - fx) * p[0] + fx * p[1]) + fy * ((1.f - fx) * p[w] + fx * p[w + 1]);
  }
  // Bilinear sampling touches only pixels at least `border` inside: border <= x < width - 1 - border.
  bool InBounds(int l, float x, float y, float border) const {
    return x >= border && y >= border && x < width(l) - 1.f - border && y < height(l) - 1.f - border;
  }

  // Asks the cache for the pixels within `radius` (+1 for bilinear) of (x, y) at level l, ahead of
  // sampling them: residuals over many keyframes read images far larger than the caches, and the
  // loads, not the arithmetic, dominate. Does nothing outside the image or without gradients.
  void Prefetch(int l, int x, int y, int radius) const {
    if (!HasGradients()) return;
    const Image<PixelFixed>& img = fixed_[l];
    if (x - radius < 0 || y - radius < 0 || x + radius + 1 >= img.width() || y + radius + 1 >= img.height()) return;
    for (int r = y - radius; r <= y + radius + 1; ++r) {
      const auto first = reinterpret_cast<uintptr_t>(img.Row(r) + x - radius) & ~uintptr_t{63};
      const auto last = reinterpret_cast<uintptr_t>(img.Row(r) + x + radius + 2) - 1;
      for (uintptr_t line = first; line <= last; line += 64) __builtin_prefetch(reinterpret_cast<const void*>(line));
    }
  }

 private:
  // Exactly one of the two is filled.
  std::vector<Image<float>> values_;      // Intensities only.
  std::vector<Image<PixelFixed>> fixed_;  // (I, dI/dx, dI/dy) in fixed point.
};

}  // namespace dsm

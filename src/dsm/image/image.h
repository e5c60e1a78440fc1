// SPDX-License-Identifier: MIT
// Image<T>: a dense row-major image owning its pixels, and bilinear sampling.
#pragma once

#include <cstdint>
#include <vector>

#include "dsm/util/check.h"

namespace dsm {

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, T fill = T()) : width_(width), height_(height) {
    DSM_CHECK(width >= 0 && height >= 0, "negative image size");
    pixels_.assign(static_cast<size_t>(width) * static_cast<size_t>(height), fill);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }
  size_t size() const { return pixels_.size(); }

  T& operator()(int x, int y) {
    DSM_DCHECK(x >= 0 && y >= 0 && x < width_ && y < height_, "pixel out of bounds");
    return pixels_[static_cast<size_t>(y) * width_ + x];
  }
  const T& operator()(int x, int y) const {
    DSM_DCHECK(x >= 0 && y >= 0 && x < width_ && y < height_, "pixel out of bounds");
    return pixels_[static_cast<size_t>(y) * width_ + x];
  }
  T* Row(int y) { return pixels_.data() + static_cast<size_t>(y) * width_; }
  const T* Row(int y) const { return pixels_.data() + static_cast<size_t>(y) * width_; }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }

  // True when bilinear sampling at (x, y) touches only pixels at least `border` inside the image.
  bool InBounds(double x, double y, double border = 0.0) const {
    return x >= border && y >= border && x <= width_ - 1.0 - border - 1e-6 &&
           y <= height_ - 1.0 - border - 1e-6;
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

// An 8-bit image as float grey values.
inline Image<float> ToFloat(const Image<uint8_t>& image) {
  Image<float> out(image.width(), image.height());
  for (size_t i = 0; i < image.size(); ++i) out.data()[i] = image.data()[i];
  return out;
}

// Bilinear interpolation at (x, y); the caller guarantees InBounds(x, y).
//   I(x, y) = (1-fx)(1-fy) I00 + fx (1-fy) I10 + (1-fx) fy I01 + fx fy I11
template <typename T>
inline float Bilinear(const Image<T>& image, float x, float y) {
  const int ix = static_cast<int>(x);
  const int iy = static_cast<int>(y);
  const float fx = x - ix;
  const float fy = y - iy;
  const T* row0 = image.Row(iy) + ix;
  const T* row1 = row0 + image.width();
  return (1.f - fy) * ((1.f - fx) * row0[0] + fx * row0[1]) + fy * ((1.f - fx) * row1[0] + fx * row1[1]);
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/geometry/undistorter.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dsm {

UndistortMode ParseUndistortMode(const std::string& name, const std::string& where) {
  if (name == "crop") return UndistortMode::kCrop;
  if (name == "full") return UndistortMode::kFull;
  throw InputError(where + ": unknown undistortion mode '" + name + "' (expected crop or full)");
}

namespace {

// Normalized-plane rectangle inside the image of the input border: the innermost point of every
// edge (sampled at each pixel) bounds the rectangle on that side.
struct Rect {
  double x_min, x_max, y_min, y_max;
};

Rect InnerRectangle(const CameraCalibration& cam) {
  Rect r{-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
         -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  // Edges sampled a hair inside so that the extreme output pixels still sample inside the image.
  const double e = 1e-3, w = cam.width - 1.0 - e, h = cam.height - 1.0 - e;
  Eigen::Vector2d xy;
  for (int v = 0; v < cam.height; ++v) {
    if (cam.Unproject({e, double(v)}, &xy)) r.x_min = std::max(r.x_min, xy.x());
    if (cam.Unproject({w, double(v)}, &xy)) r.x_max = std::min(r.x_max, xy.x());
  }
  for (int u = 0; u < cam.width; ++u) {
    if (cam.Unproject({double(u), e}, &xy)) r.y_min = std::max(r.y_min, xy.y());
    if (cam.Unproject({double(u), h}, &xy)) r.y_max = std::min(r.y_max, xy.y());
  }
  return r;
}

}  // namespace

Undistorter::Undistorter(const CameraCalibration& input, const Options& options) : input_(input) {
  input.Validate("camera calibration");
  DSM_CHECK(options.size_multiple >= 1, "size_multiple must be positive");
  const int out_w = input.width / options.size_multiple * options.size_multiple;
  const int out_h = input.height / options.size_multiple * options.size_multiple;
  output_.width = out_w;
  output_.height = out_h;

  if (input.IsPinhole()) {
    pure_crop_ = true;
    crop_x_ = (input.width - out_w) / 2;
    crop_y_ = (input.height - out_h) / 2;
    output_.fx = input.fx;
    output_.fy = input.fy;
    output_.cx = input.cx - crop_x_;
    output_.cy = input.cy - crop_y_;
    valid_ = Image<uint8_t>(out_w, out_h, 1);
    return;
  }

  if (options.mode == UndistortMode::kFull) {
    output_.fx = input.fx;
    output_.fy = input.fy;
    output_.cx = input.cx - 0.5 * (input.width - out_w);
    output_.cy = input.cy - 0.5 * (input.height - out_h);
  } else {
    const Rect r = InnerRectangle(input);
    if (!(r.x_max > r.x_min) || !(r.y_max > r.y_min) || !std::isfinite(r.x_min + r.x_max + r.y_min + r.y_max)) {
      throw InputError("camera calibration: the distortion leaves no valid undistorted view");
    }
    // Pixel 0 maps to x_min and pixel out_w - 1 to x_max.
    output_.fx = (out_w - 1.0) / (r.x_max - r.x_min);
    output_.fy = (out_h - 1.0) / (r.y_max - r.y_min);
    output_.cx = -r.x_min * output_.fx;
    output_.cy = -r.y_min * output_.fy;
  }

  map_x_.resize(static_cast<size_t>(out_w) * out_h);
  map_y_.resize(map_x_.size());
  valid_ = Image<uint8_t>(out_w, out_h, 0);
  // Sampling is valid where all four bilinear neighbours are inside the input image.
  const Image<float> bounds(input.width, input.height);
  for (int v = 0; v < out_h; ++v) {
    for (int u = 0; u < out_w; ++u) {
      const Eigen::Vector2d src = SourcePixel(u, v);
      const size_t i = static_cast<size_t>(v) * out_w + u;
      map_x_[i] = static_cast<float>(src.x());
      map_y_[i] = static_cast<float>(src.y());
      valid_(u, v) = src.allFinite() && bounds.InBounds(map_x_[i], map_y_[i]) ? 1 : 0;
    }
  }
  if (ValidFraction() < 0.5) {
    throw InputError("camera calibration: less than half of the undistorted view is valid");
  }
  offset_.assign(map_x_.size(), 0);
  frac_x_.assign(map_x_.size(), 0.f);
  frac_y_.assign(map_x_.size(), 0.f);
  for (int v = 0; v < out_h; ++v) {
    for (int u = 0; u < out_w; ++u) {
      const size_t i = static_cast<size_t>(v) * out_w + u;
      if (!valid_(u, v)) continue;
      const int ix = static_cast<int>(map_x_[i]), iy = static_cast<int>(map_y_[i]);
      offset_[i] = iy * input.width + ix;
      frac_x_[i] = map_x_[i] - ix;
      frac_y_[i] = map_y_[i] - iy;
    }
  }
  const int64_t input_size = static_cast<int64_t>(input.width) * input.height;
  run_ok_.assign(static_cast<size_t>(out_w / 8) * out_h, 0);
  for (int v = 0; v < out_h; ++v) {
    for (int r = 0; r < out_w / 8; ++r) {
      bool ok = true;
      for (int u = 8 * r; u < 8 * r + 8; ++u) {
        const size_t i = static_cast<size_t>(v) * out_w + u;
        ok = ok && valid_(u, v) && offset_[i] + int64_t{input.width} + 4 <= input_size;
      }
      run_ok_[static_cast<size_t>(v) * (out_w / 8) + r] = ok;
    }
  }
}

Eigen::Vector2d Undistorter::SourcePixel(double u, double v) const {
  if (pure_crop_) return {u + crop_x_, v + crop_y_};
  return input_.Project(output_.Unproject(u, v));
}

double Undistorter::ValidFraction() const {
  size_t n = 0;
  for (size_t i = 0; i < valid_.size(); ++i) n += valid_.data()[i];
  return valid_.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(valid_.size());
}

Image<float> Undistorter::Apply(const Image<float>& distorted) const { return Remap(distorted); }

Image<float> Undistorter::Apply(const Image<uint8_t>& distorted) const {
  Image<float> out;
  if (!pure_crop_ && Remap8(distorted, &out)) return out;
  return Remap(distorted);
}

template <typename T>
Image<float> Undistorter::Remap(const Image<T>& distorted) const {
  DSM_CHECK(distorted.width() == input_.width && distorted.height() == input_.height,
            "image size differs from the calibration");
  Image<float> out(output_.width, output_.height, 0.f);
  if (pure_crop_) {
    for (int v = 0; v < output_.height; ++v) {
      std::copy_n(distorted.Row(v + crop_y_) + crop_x_, output_.width, out.Row(v));
    }
    return out;
  }
  for (int v = 0; v < output_.height; ++v) {
    float* row = out.Row(v);
    const uint8_t* ok = valid_.Row(v);
    const size_t base = static_cast<size_t>(v) * output_.width;
    for (int u = 0; u < output_.width; ++u) {
      if (ok[u]) row[u] = Bilinear(distorted, map_x_[base + u], map_y_[base + u]);
    }
  }
  return out;
}

}  // namespace dsm

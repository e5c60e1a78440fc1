// SPDX-License-Identifier: MIT
// Undistortion to an ideal pinhole camera with a precomputed remap and a validity mask.
//
// For every output pixel (u, v) of the pinhole camera P' the source pixel in the input image is
//   src(u, v) = Project_input( ((u - cx') / fx', (v - cy') / fy', 1) ),
// computed once; Apply() then samples the input bilinearly at src (0 where src is outside).
//
// The output size is the input size rounded down to a multiple of `size_multiple` (cropping equally
// on both sides), so that every pyramid level halves exactly, whatever the input size (KITTI's
// 1241 px becomes 1232 px).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"

namespace dsm {

enum class UndistortMode {
  kCrop,  // Largest axis-aligned view whose pixels all come from inside the input image.
  kFull,  // Keep the input focal lengths and principal point; pixels outside stay invalid.
};

UndistortMode ParseUndistortMode(const std::string& name, const std::string& where);

class Undistorter {
 public:
  struct Options {
    UndistortMode mode = UndistortMode::kCrop;  // Ignored for pinhole inputs (exact crop instead).
    int size_multiple = 16;                     // Output width and height divide by this (>= 1).
  };

  // Throws InputError if the calibration is invalid or no valid output view exists.
  Undistorter(const CameraCalibration& input, const Options& options);

  const PinholeCamera& output() const { return output_; }
  const CameraCalibration& input() const { return input_; }
  // 1 where the output pixel maps inside the input image, else 0.
  const Image<uint8_t>& valid_mask() const { return valid_; }
  double ValidFraction() const;

  // Undistorts an image of the input size (checked). An 8-bit input gives the same floats as its
  // float copy would (every 8-bit value is exact in float), without the copy.
  Image<float> Apply(const Image<float>& distorted) const;
  Image<float> Apply(const Image<uint8_t>& distorted) const;

  // Source pixel in the input image for output pixel (u, v).
  Eigen::Vector2d SourcePixel(double u, double v) const;

 private:
  template <typename T>
  Image<float> Remap(const Image<T>& distorted) const;
  // Remap of an 8-bit image into *out, eight output pixels at a time (undistorter_remap.cc); false
  // when the CPU has no AVX2 (Remap then).
  bool Remap8(const Image<uint8_t>& distorted, Image<float>* out) const;

  CameraCalibration input_;
  PinholeCamera output_;
  bool pure_crop_ = false;  // Pinhole input: integer shift, no interpolation.
  int crop_x_ = 0, crop_y_ = 0;
  std::vector<float> map_x_, map_y_;
  Image<uint8_t> valid_;
  // Per output pixel, what Bilinear derives from (map_x_, map_y_): the input index of the top-left
  // neighbour, iy w + ix, and the fractions x - ix, y - iy (0 where invalid). Per run of 8 output
  // pixels in a row: 1 when all are valid and their 32-bit reads at both rows stay in the image.
  std::vector<int32_t> offset_;
  std::vector<float> frac_x_, frac_y_;
  std::vector<uint8_t> run_ok_;
};

}  // namespace dsm

// SPDX-License-Identifier: MIT
// Photometric calibration of a camera (the model of the paper's eq. 1, after Engel et al.):
//   I(x) = G(t V(x) B(x))
// with G the camera response, V the vignette, t the exposure time and B the scene irradiance.
// Given G^-1 (256 values) and V, a raw 8-bit pixel becomes
//   t B(x) = G^-1(I(x)) / V(x);
// the exposure t is kept apart (it enters the affine brightness model as a known factor).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "dsm/image/image.h"

namespace dsm {

class PhotometricCalibration {
 public:
  // Identity: linear response, no vignette.
  PhotometricCalibration();

  // G^-1 values for pixel values 0..255; must be finite and strictly increasing. They are rescaled
  // so that G^-1(0) = 0 and G^-1(255) = 255. Throws InputError naming `source` otherwise.
  void SetInverseResponse(const std::array<double, 256>& g_inv, const std::string& source);
  // V(x) per pixel, any positive scale (normalised so its maximum is 1); throws InputError naming
  // `source` when a value is not positive.
  void SetVignette(const Image<float>& vignette, const std::string& source);

  bool has_response() const { return has_response_; }
  bool has_vignette() const { return !vignette_.empty(); }
  const std::array<float, 256>& inverse_response() const { return g_inv_; }
  const Image<float>& vignette() const { return vignette_; }

  // t B(x) = G^-1(I(x)) / V(x); the image size must match the vignette when one is set.
  Image<float> ToIrradiance(const Image<uint8_t>& raw) const;

 private:
  std::array<float, 256> g_inv_;
  bool has_response_ = false;
  Image<float> vignette_;  // Empty when there is none; else max 1.
};

}  // namespace dsm

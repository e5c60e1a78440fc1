// SPDX-License-Identifier: MIT
#include "dsm/photometric/photometric_calibration.h"

#include <algorithm>
#include <cmath>

#include "dsm/util/check.h"

namespace dsm {

PhotometricCalibration::PhotometricCalibration() {
  for (int i = 0; i < 256; ++i) g_inv_[i] = static_cast<float>(i);
}

void PhotometricCalibration::SetInverseResponse(const std::array<double, 256>& g_inv, const std::string& source) {
  for (int i = 0; i < 256; ++i) {
    if (!std::isfinite(g_inv[i])) throw InputError(source + ": inverse response value " + std::to_string(i) + " is not a number");
    if (i > 0 && !(g_inv[i] > g_inv[i - 1]))
      throw InputError(source + ": inverse response must increase strictly (value " + std::to_string(i) + ")");
  }
  const double lo = g_inv[0], hi = g_inv[255];
  for (int i = 0; i < 256; ++i) g_inv_[i] = static_cast<float>(255.0 * (g_inv[i] - lo) / (hi - lo));
  has_response_ = true;
}

void PhotometricCalibration::SetVignette(const Image<float>& vignette, const std::string& source) {
  if (vignette.empty()) throw InputError(source + ": vignette image is empty");
  float max_value = 0.f;
  for (size_t i = 0; i < vignette.size(); ++i) {
    const float v = vignette.data()[i];
    if (!(v > 0.f) || !std::isfinite(v)) throw InputError(source + ": vignette values must be positive");
    max_value = std::max(max_value, v);
  }
  vignette_ = vignette;
  for (size_t i = 0; i < vignette_.size(); ++i) vignette_.data()[i] /= max_value;
}

Image<float> PhotometricCalibration::ToIrradiance(const Image<uint8_t>& raw) const {
  if (has_vignette()) {
    DSM_CHECK(raw.width() == vignette_.width() && raw.height() == vignette_.height(),
              "image size differs from the vignette");
  }
  Image<float> out(raw.width(), raw.height());
  for (size_t i = 0; i < raw.size(); ++i) {
    float v = g_inv_[raw.data()[i]];
    if (has_vignette()) v /= vignette_.data()[i];
    out.data()[i] = v;
  }
  return out;
}

}  // namespace dsm

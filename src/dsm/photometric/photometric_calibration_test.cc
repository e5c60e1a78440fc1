// SPDX-License-Identifier: MIT
#include "dsm/photometric/photometric_calibration.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(PhotometricCalibration, IdentityByDefault) {
  const PhotometricCalibration calib;
  Image<uint8_t> raw(3, 2, 77);
  EXPECT_FLOAT_EQ(calib.ToIrradiance(raw)(2, 1), 77.f);
}

TEST(PhotometricCalibration, UndoesGammaResponseAndVignette) {
  // G(x) = 255 (x / 255)^(1/2.2): G^-1(I) = 255 (I / 255)^2.2; vignette falls off to 0.5.
  std::array<double, 256> g_inv;
  for (int i = 0; i < 256; ++i) g_inv[i] = 2.0 * std::pow(i / 255.0, 2.2) + 1.0;  // any affine scale
  Image<float> vignette(4, 1);
  for (int x = 0; x < 4; ++x) vignette(x, 0) = 2.f * (1.f - x / 6.f);  // max 2 -> normalised to 1
  PhotometricCalibration calib;
  calib.SetInverseResponse(g_inv, "pcalib.txt");
  calib.SetVignette(vignette, "vignette.png");
  // A scene of constant irradiance 100 (in G^-1 units), imaged through V and G.
  Image<uint8_t> raw(4, 1);
  for (int x = 0; x < 4; ++x) {
    const double v = 1.0 - x / 6.0;
    raw(x, 0) = static_cast<uint8_t>(std::lround(255.0 * std::pow(100.0 * v / 255.0, 1.0 / 2.2)));
  }
  const Image<float> irr = calib.ToIrradiance(raw);
  for (int x = 0; x < 4; ++x) EXPECT_NEAR(irr(x, 0), 100.f, 1.5f) << x;
}

TEST(PhotometricCalibration, RejectsBadInput) {
  PhotometricCalibration calib;
  std::array<double, 256> flat{};
  EXPECT_THROW(calib.SetInverseResponse(flat, "pcalib.txt"), InputError);
  Image<float> bad(2, 2, 1.f);
  bad(1, 1) = 0.f;
  EXPECT_THROW(calib.SetVignette(bad, "vignette.png"), InputError);
}

}  // namespace
}  // namespace dsm

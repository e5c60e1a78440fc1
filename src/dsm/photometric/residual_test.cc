// SPDX-License-Identifier: MIT
// Jacobians of the photometric residual against central differences (pose, inverse depth, affine).
#include "dsm/photometric/residual.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "dsm/lie/se3.h"

namespace dsm {
namespace {

// A smooth image (wavelengths of hundreds of pixels), so that interpolated gradients match the
// derivative of the bilinear samples. Its contrast is kContrast times that of an 8-bit image,
// within the pyramid's fixed-point range (0..1023), so that the quantisation (1/64 grey level,
// 1/32 per pixel) is small against the gradients; Jacobians and their tolerances scale with it.
constexpr double kContrast = 5.0;
ImagePyramid SmoothImage(int w, int h, float phase) {
  Image<float> img(w, h);
  const float c = static_cast<float>(kContrast);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(x, y) = 500.f + c * (80.f * std::sin(0.03f * x + phase) * std::cos(0.025f * y - phase) + 0.2f * x);
  return ImagePyramid(img, 2);
}

struct PairSetup {
  PinholeCamera cam{160, 128, 150, 150, 79.5, 63.5};
  ImagePyramid host = SmoothImage(160, 128, 0.3f);
  ImagePyramid target = SmoothImage(160, 128, 0.9f);
  SE3d target_from_host;
  AffineBrightness ah{0.1, 5.0}, at{-0.05, -3.0};
  float idepth = 0.45f;

  PairSetup() {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0.05, -0.03, 0.02, 0.01, -0.02, 0.015;
    target_from_host = SE3d::Exp(xi);
  }
  Interpolation interpolation = Interpolation::kBilinear;

  bool Eval(const SE3d& T, float rho, const AffineBrightness& h, const AffineBrightness& t, bool jac,
            ObservationResiduals* out) const {
    HostPatch patch;
    if (!SampleHostPatch(host, 0, Eigen::Vector2f(70.3f, 60.6f), interpolation, &patch)) return false;
    ObservationInput in;
    in.camera = &cam;
    in.target = &target;
    in.level = 0;
    in.R = T.Rotation().cast<float>();
    in.t = T.Translation().cast<float>();
    in.idepth = rho;
    in.host_affine = h;
    in.target_affine = t;
    in.host_exposure = 10.0;
    in.target_exposure = 12.0;
    return EvaluateObservation(patch, in, jac, out);
  }
};

class Residual : public ::testing::TestWithParam<Interpolation> {};

TEST_P(Residual, JacobiansMatchCentralDifferences) {
  PairSetup s;
  s.interpolation = GetParam();
  ObservationResiduals base;
  ASSERT_TRUE(s.Eval(s.target_from_host, s.idepth, s.ah, s.at, true, &base));
  const double h = 2e-3;  // float residuals: a step well above their rounding
  ObservationResiduals plus, minus;
  // Pose: left increment of target_from_host.
  for (int j = 0; j < 6; ++j) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d(j) = h;
    ASSERT_TRUE(s.Eval(SE3d::Exp(d) * s.target_from_host, s.idepth, s.ah, s.at, false, &plus));
    ASSERT_TRUE(s.Eval(SE3d::Exp(-d) * s.target_from_host, s.idepth, s.ah, s.at, false, &minus));
    for (int k = 0; k < kPatternSize; ++k) {
      const double numeric = (plus.r[k] - minus.r[k]) / (2 * h);
      EXPECT_NEAR(base.J_pose(k, j), numeric, 0.03 * std::abs(numeric) + 0.3 * kContrast) << "pose " << j << " pixel " << k;
    }
  }
  // Inverse depth.
  const float hr = 1e-3f;
  ASSERT_TRUE(s.Eval(s.target_from_host, s.idepth + hr, s.ah, s.at, false, &plus));
  ASSERT_TRUE(s.Eval(s.target_from_host, s.idepth - hr, s.ah, s.at, false, &minus));
  for (int k = 0; k < kPatternSize; ++k) {
    const double numeric = (plus.r[k] - minus.r[k]) / (2 * hr);
    EXPECT_NEAR(base.J_idepth(k), numeric, 0.03 * std::abs(numeric) + 0.3 * kContrast) << "idepth pixel " << k;
  }
  // Affine: a_h, b_h, a_t, b_t (exactly linear or exponential: tight tolerance).
  for (int j = 0; j < 4; ++j) {
    AffineBrightness hp = s.ah, hm = s.ah, tp = s.at, tm = s.at;
    double* plus_param[] = {&hp.a, &hp.b, &tp.a, &tp.b};
    double* minus_param[] = {&hm.a, &hm.b, &tm.a, &tm.b};
    const double step = j % 2 ? 0.5 : h;  // r is linear in b: a large step is exact and above rounding
    *plus_param[j] += step;
    *minus_param[j] -= step;
    ASSERT_TRUE(s.Eval(s.target_from_host, s.idepth, hp, tp, false, &plus));
    ASSERT_TRUE(s.Eval(s.target_from_host, s.idepth, hm, tm, false, &minus));
    for (int k = 0; k < kPatternSize; ++k) {
      const double numeric = (plus.r[k] - minus.r[k]) / (2 * step);
      EXPECT_NEAR(base.J_affine(k, j), numeric, 1e-3 * std::abs(numeric) + 2e-3) << "affine " << j << " pixel " << k;
    }
  }
}

TEST_P(Residual, ZeroForAConsistentPair) {
  // Target = host image seen from the same pose with a known brightness change: residuals vanish.
  PairSetup s;
  s.interpolation = GetParam();
  s.target = s.host;
  ObservationResiduals out;
  const AffineBrightness same{0.0, 0.0};
  HostPatch patch;
  ASSERT_TRUE(SampleHostPatch(s.host, 0, Eigen::Vector2f(50.f, 40.f), s.interpolation, &patch));
  ObservationInput in;
  in.camera = &s.cam;
  in.target = &s.target;
  in.R.setIdentity();
  in.t.setZero();
  in.idepth = 0.5f;
  in.host_affine = same;
  in.target_affine = same;
  ASSERT_TRUE(EvaluateObservation(patch, in, false, &out));
  for (float r : out.r) EXPECT_NEAR(r, 0.f, 1e-4f);
  EXPECT_NEAR(out.center_target.x(), 50.f, 1e-4f);
  EXPECT_NEAR(out.target_depth, 2.f, 1e-5f);
  // Point behind the target camera: rejected.
  in.t = Eigen::Vector3f(0, 0, -3.f);
  EXPECT_FALSE(EvaluateObservation(patch, in, false, &out));
}

TEST(ResidualInterpolation, BSplinePatchesSampleTheSmoothSurface) {
  // Host and target sample alike: the patch holds the B-spline's values, and a target
  // observation reads the B-spline there too (zero residual against the same image at a
  // sub-pixel centre, where bilinear and B-spline values differ).
  const PairSetup s;
  HostPatch bilinear, bspline;
  const Eigen::Vector2f centre(50.5f, 40.5f);
  ASSERT_TRUE(SampleHostPatch(s.host, 0, centre, Interpolation::kBilinear, &bilinear));
  ASSERT_TRUE(SampleHostPatch(s.host, 0, centre, Interpolation::kBSpline, &bspline));
  EXPECT_EQ(bspline.interpolation, Interpolation::kBSpline);
  double differ = 0.0;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = centre.x() + kPattern[k][0], y = centre.y() + kPattern[k][1];
    EXPECT_EQ(bspline.value[k], s.host.SampleBSpline(0, x, y)[0]);
    EXPECT_EQ(bilinear.value[k], s.host.Sample(0, x, y)[0]);
    differ = std::max(differ, static_cast<double>(std::abs(bspline.value[k] - bilinear.value[k])));
  }
  EXPECT_GT(differ, 0.01);  // A smooth image: the blur is slight, but there.
  // Against the same image at the same pose: zero only if the target is read by the B-spline too.
  ObservationInput in;
  in.camera = &s.cam;
  in.target = &s.host;
  in.R.setIdentity();
  in.t.setZero();
  ObservationResiduals out;
  ASSERT_TRUE(EvaluateObservation(bspline, in, false, &out));
  for (float r : out.r) EXPECT_NEAR(r, 0.f, 1e-3f);
  // The B-spline needs one more pixel of border.
  HostPatch edge;
  EXPECT_TRUE(SampleHostPatch(s.host, 0, Eigen::Vector2f(3.5f, 40.f), Interpolation::kBilinear, &edge));
  EXPECT_FALSE(SampleHostPatch(s.host, 0, Eigen::Vector2f(3.5f, 40.f), Interpolation::kBSpline, &edge));
}

INSTANTIATE_TEST_SUITE_P(BothInterpolations, Residual,
                         ::testing::Values(Interpolation::kBilinear, Interpolation::kBSpline),
                         [](const ::testing::TestParamInfo<Interpolation>& param) {
                           return param.param == Interpolation::kBSpline ? "BSpline" : "Bilinear";
                         });

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// The texture-loss test (texture_loss.h): on hand-made pattern values, and on observations
// evaluated between real images.
#include "dsm/photometric/texture_loss.h"

#include <cmath>

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

// A host pattern with variance 100 (values 100 +- 10), and residuals that leave the target with
// `contrast` times the host's deviations from the mean (plus an offset): V_t = contrast^2 V_h.
struct Pattern {
  HostPatch host;
  ObservationResiduals res;
  Pattern(double contrast, float depth_ratio = 1.f) {
    for (int k = 0; k < kPatternSize; ++k) {
      const float deviation = (k % 2 == 0 ? 10.f : -10.f);
      host.value[k] = 100.f + deviation;
      const float target = 130.f + static_cast<float>(contrast) * deviation;  // I_h - r
      res.r[k] = host.value[k] - target;
    }
    res.target_depth = 2.f * depth_ratio;  // The host depth is 1 / idepth = 2.
  }
};
constexpr float kIdepth = 0.5f;

TextureLossOptions On() {
  TextureLossOptions options;
  options.max_variance_ratio = kTextureLossRatio;
  return options;
}

TEST(TextureLoss, TargetKeepingTheTextureIsNotLost) {
  const TextureLossOptions options = On();
  EXPECT_FALSE(TextureLost(Pattern(1.0).host, Pattern(1.0).res, kIdepth, options));
  // sqrt(0.3) of the contrast keeps 30 % of the variance: above the 25 % share.
  const Pattern kept(std::sqrt(0.3));
  EXPECT_FALSE(TextureLost(kept.host, kept.res, kIdepth, options));
}

TEST(TextureLoss, FlatTargetLosesTheTexture) {
  const TextureLossOptions options = On();
  const Pattern flat(0.0), faint(std::sqrt(0.2));
  EXPECT_TRUE(TextureLost(flat.host, flat.res, kIdepth, options));
  EXPECT_TRUE(TextureLost(faint.host, faint.res, kIdepth, options));
}

TEST(TextureLoss, NotJudgedFromFartherOrMuchNearerOnFaintHostsOrWhenOff) {
  TextureLossOptions options = On();
  // Seen from 1.5x the host's depth the texture is compressed into fewer pixels, from 0.7x the
  // samples cover less of it: not judged. Within 1.25x either way it is.
  const Pattern far(0.0, 1.5f), near(0.0, 1.2f), closer(0.0, 0.85f), much_closer(0.0, 0.7f);
  EXPECT_FALSE(TextureLost(far.host, far.res, kIdepth, options));
  EXPECT_TRUE(TextureLost(near.host, near.res, kIdepth, options));
  EXPECT_TRUE(TextureLost(closer.host, closer.res, kIdepth, options));
  EXPECT_FALSE(TextureLost(much_closer.host, much_closer.res, kIdepth, options));
  // A host with less variance than min_host_variance (100 here) has nothing to lose.
  options.min_host_variance = 101.0;
  EXPECT_FALSE(TextureLost(near.host, near.res, kIdepth, options));
  EXPECT_FALSE(TextureLost(near.host, near.res, kIdepth, TextureLossOptions{}));  // Off by default.
}

// Real observations: a textured host seen in the same image (identity pose) keeps its texture;
// in a uniform image (a plain surface in front of the point) it is lost.
TEST(TextureLoss, EvaluatedObservations) {
  Image<float> textured(96, 96), plain(96, 96);
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      textured(x, y) = 120.f + 40.f * std::sin(0.9f * x) * std::cos(0.7f * y);
      plain(x, y) = 120.f;
    }
  const ImagePyramid host(textured, 1), same(textured, 1), flat(plain, 1);
  const PinholeCamera cam{96, 96, 80, 80, 47.5, 47.5};
  for (Interpolation interpolation : {Interpolation::kBilinear, Interpolation::kBSpline}) {
    HostPatch patch;
    ASSERT_TRUE(SampleHostPatch(host, 0, Eigen::Vector2f(40.3f, 50.6f), interpolation, &patch));
    ObservationInput in;
    in.camera = &cam;
    in.R.setIdentity();
    in.t = Eigen::Vector3f(0.f, 0.f, 0.f);
    in.idepth = 0.5f;
    ObservationResiduals res;
    in.target = &same;
    ASSERT_TRUE(EvaluateObservation(patch, in, false, &res));
    EXPECT_FALSE(TextureLost(patch, res, in.idepth, On()));
    in.target = &flat;
    ASSERT_TRUE(EvaluateObservation(patch, in, false, &res));
    EXPECT_TRUE(TextureLost(patch, res, in.idepth, On()));
  }
}

TEST(TextureLoss, ValidateNamesTheOption) {
  TextureLossOptions options;
  options.max_variance_ratio = 1.0;
  EXPECT_THROW(options.Validate(), InputError);
  options = TextureLossOptions{};
  options.max_depth_ratio = 0.9;
  EXPECT_THROW(options.Validate(), InputError);
  options = TextureLossOptions{};
  options.min_host_variance = -1.0;
  EXPECT_THROW(options.Validate(), InputError);
  EXPECT_NO_THROW(TextureLossOptions{}.Validate());
}

}  // namespace
}  // namespace dsm

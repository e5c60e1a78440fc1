// SPDX-License-Identifier: MIT
#include "dsm/mapping/observation_check.h"

#include <gtest/gtest.h>

#include "dsm/optimization/pba_world.h"

namespace dsm {
namespace {

// Share of keyframe 0's points that look like themselves in keyframe `target`.
double ConsistentShare(const testing::World& w, int target) {
  const ErrorModel model = DefaultErrorModel(RobustOptions{});
  int n = 0, consistent = 0;
  for (int i = 0; i < w.map.NumPoints(); ++i) {
    const Point& p = w.map.point(i);
    if (p.host != 0) continue;
    ++n;
    consistent += LooksConsistent(w.map, w.seq.camera, p, target, model, 0.3);
  }
  return static_cast<double>(consistent) / n;
}

TEST(LooksConsistent, TruePosesAndDepthsMatchAndAnotherImageDoesNot) {
  testing::World w;
  testing::BuildWorld({0, 4, 8}, &w);
  EXPECT_GT(ConsistentShare(w, 2), 0.9);

  // Keyframe 2 now shows something else where the points are (a mirrored image: what a new
  // occluder in front of them would do).
  Keyframe& kf = w.map.keyframe(2);
  const ImagePyramid& original = kf.Pyramid();
  const int width = original.width(0);
  Image<float> mirrored(width, original.height(0));
  for (int y = 0; y < mirrored.height(); ++y)
    for (int x = 0; x < width; ++x) mirrored(x, y) = original.Value(0, width - 1 - x, y);
  kf.pyramid = std::make_shared<const ImagePyramid>(mirrored, kf.Pyramid().levels());
  EXPECT_LT(ConsistentShare(w, 2), 0.3);
}

TEST(TextureGone, APlainSurfaceInFrontTakesTheTextureAway) {
  testing::World w;
  testing::BuildWorld({0, 4, 8}, &w);
  TextureLossOptions options;
  options.max_variance_ratio = kTextureLossRatio;
  const auto gone_share = [&](int target) {
    int n = 0, gone = 0;
    for (int i = 0; i < w.map.NumPoints(); ++i) {
      const Point& p = w.map.point(i);
      if (p.host != 0 || PatternVariance(p.patch.value) < options.min_host_variance) continue;
      ++n;
      gone += TextureGone(w.map, w.seq.camera, p, target, options);
    }
    return static_cast<double>(gone) / n;
  };
  EXPECT_LT(gone_share(2), 0.1);
  // Keyframe 2 now shows a plain grey surface with a little noise everywhere.
  Keyframe& kf = w.map.keyframe(2);
  Image<float> plain(kf.Pyramid().width(0), kf.Pyramid().height(0));
  for (int y = 0; y < plain.height(); ++y)
    for (int x = 0; x < plain.width(); ++x) plain(x, y) = 120.f + static_cast<float>((x * 7 + y * 13) % 5);
  kf.pyramid = std::make_shared<const ImagePyramid>(plain, kf.Pyramid().levels());
  EXPECT_GT(gone_share(2), 0.9);
  options.max_variance_ratio = 0.0;  // The test is off.
  EXPECT_EQ(gone_share(2), 0.0);
}

TEST(LooksConsistent, PatternLeavingTheImageIsNotConsistent) {
  testing::World w;
  testing::BuildWorld({0, 4}, &w);
  Point p = w.map.point(0);
  p.pixel = Eigen::Vector2f(0.5f, 0.5f);  // The host pattern cannot be sampled.
  const Point& added = w.map.point(w.map.AddPoint(p));
  EXPECT_FALSE(added.patch_ok);
  EXPECT_FALSE(LooksConsistent(w.map, w.seq.camera, added, 1, DefaultErrorModel(RobustOptions{}), 0.3));
}

}  // namespace
}  // namespace dsm

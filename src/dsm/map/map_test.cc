// SPDX-License-Identifier: MIT
#include "dsm/map/map.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace dsm {
namespace {

std::unique_ptr<Keyframe> MakeKeyframe(float phase) {
  Image<float> image(32, 16);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image(x, y) = 120.f + 100.f * std::sin(0.37f * x + phase) * std::cos(0.21f * y);
  auto kf = std::make_unique<Keyframe>();
  kf->pyramid = std::make_shared<const ImagePyramid>(image, 3);
  return kf;
}

// Released pyramids are rebuilt exactly from the compact image; the ones used in the last epochs
// stay; points keep their own host patch throughout.
TEST(Map, ReleasesUnusedPyramidsAndRebuildsThemExactlyFromTheCompactImage) {
  Map map;
  for (int k = 0; k < 3; ++k) map.AddKeyframe(MakeKeyframe(0.5f * k));
  const ImagePyramid original = map.keyframe(0).Pyramid();
  Point p;
  p.host = 0;
  p.pixel = Eigen::Vector2f(10.f, 7.f);
  const int pid = map.AddPoint(p);
  ASSERT_TRUE(map.point(pid).patch_ok);
  const HostPatch patch = map.point(pid).patch;

  EXPECT_EQ(map.ReleaseUnusedPyramids(2), 0);  // All made in this epoch.
  EXPECT_EQ(map.LoadPyramids({2}), 0);          // Loaded: only marked used.
  EXPECT_EQ(map.ReleaseUnusedPyramids(2), 0);
  EXPECT_EQ(map.ReleaseUnusedPyramids(2), 2);   // 0 and 1 unused for two epochs; 2 used one ago.
  EXPECT_EQ(map.NumLoadedPyramids(), 1);
  EXPECT_EQ(map.keyframe(0).pyramid, nullptr);
  // Released, a keyframe holds its compact image; loaded, only the pyramid (the same values).
  const Image<uint16_t> compact = original.FixedLevel0();
  ASSERT_EQ(map.keyframe(0).image.size(), compact.size());
  EXPECT_TRUE(std::equal(compact.data(), compact.data() + compact.size(), map.keyframe(0).image.data()));
  EXPECT_EQ(map.keyframe(2).image.size(), 0u);
  const Image<uint16_t> from_pyramid = map.keyframe(2).Level0();
  const Image<uint16_t> expected = map.keyframe(2).Pyramid().FixedLevel0();
  EXPECT_TRUE(std::equal(expected.data(), expected.data() + expected.size(), from_pyramid.data()));
  EXPECT_EQ(map.keyframe(0).width(), 32);
  EXPECT_EQ(map.keyframe(2).height(), 16);
  EXPECT_EQ(map.point(pid).patch.value, patch.value);

  EXPECT_EQ(map.LoadPyramids({0, 0, 1}), 2);
  EXPECT_EQ(map.NumLoadedPyramids(), 3);
  EXPECT_EQ(map.NumPyramidsRebuilt(), 2);
  EXPECT_EQ(map.keyframe(0).image.size(), 0u);
  const ImagePyramid& rebuilt = map.keyframe(0).Pyramid();
  ASSERT_EQ(rebuilt.levels(), original.levels());
  for (int l = 0; l < rebuilt.levels(); ++l)
    for (int y = 0; y < rebuilt.height(l); ++y)
      for (int x = 0; x < rebuilt.width(l); ++x) {
        ASSERT_EQ(rebuilt.At(l, x, y), original.At(l, x, y)) << "level " << l << " pixel " << x << ", " << y;
      }
  EXPECT_EQ(map.keyframe(1).Intensity(5, 5), map.keyframe(1).Pyramid().At(0, 5, 5)[0]);
}

// A retired keyframe keeps its pose alone; a point re-hosted moves to its new host's lists with a
// patch of that host; the map kept without retired keyframes is numbered anew throughout; and a
// map cut back to what it had drops what came after, observations included.
TEST(Map, RetiresRehostsAndDropsKeyframes) {
  Map map;
  for (int k = 0; k < 4; ++k) map.AddKeyframe(MakeKeyframe(0.5f * k));
  map.keyframe(1).cam_from_world = SE3d::Exp((Eigen::Matrix<double, 6, 1>() << 0.1, 0, 0, 0, 0, 0).finished());
  const auto add = [&map](int host, float x, std::vector<int> targets) {
    Point p;
    p.host = host;
    p.pixel = Eigen::Vector2f(x, 7.f);
    for (int t : targets) p.observations.push_back({t, false});
    return map.AddPoint(p);
  };
  const int a = add(0, 8.f, {1, 2, 3}), b = add(1, 10.f, {0, 2}), c = add(1, 12.f, {3}), d = add(3, 9.f, {1});

  map.Rehost(b, 2, Eigen::Vector2f(11.f, 6.f), 0.5f);
  EXPECT_EQ(map.point(b).host, 2);
  EXPECT_EQ(map.point(b).observations.size(), 1u);  // Its observation in keyframe 2 went.
  EXPECT_EQ(map.keyframe(2).points, std::vector<int>{b});
  EXPECT_EQ(map.keyframe(1).points, std::vector<int>{c});
  HostPatch expected;
  ASSERT_TRUE(SampleHostPatch(map.keyframe(2).Pyramid(), 0, Eigen::Vector2f(11.f, 6.f), Interpolation::kBilinear,
                              &expected));
  EXPECT_EQ(map.point(b).patch.value, expected.value);

  const SE3d pose = map.keyframe(1).cam_from_world;
  map.Retire(1);
  EXPECT_TRUE(map.keyframe(1).retired);
  EXPECT_TRUE(map.point(c).removed);
  EXPECT_EQ(map.keyframe(1).pyramid, nullptr);
  EXPECT_EQ(map.keyframe(1).image.size(), 0u);
  EXPECT_EQ(map.keyframe(1).cam_from_world.Matrix(), pose.Matrix());
  EXPECT_EQ(map.point(a).observations.size(), 2u);  // 2 and 3.
  EXPECT_TRUE(map.point(d).observations.empty());

  const std::vector<int> id = map.DropRetired();
  EXPECT_EQ(id, (std::vector<int>{0, -1, 1, 2}));
  ASSERT_EQ(map.NumKeyframes(), 3);
  ASSERT_EQ(map.NumPoints(), 3);  // a, b, d; c went with its host.
  EXPECT_EQ(map.point(0).observations[0].target, 1);
  EXPECT_EQ(map.point(0).observations[1].target, 2);
  EXPECT_EQ(map.point(1).host, 1);
  EXPECT_EQ(map.point(2).host, 2);
  EXPECT_EQ(map.keyframe(2).points, std::vector<int>{2});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(map.keyframe(k).id, k);

  map.KeepFirst(2, 2);
  EXPECT_EQ(map.NumKeyframes(), 2);
  EXPECT_EQ(map.NumPoints(), 2);
  EXPECT_EQ(map.point(0).observations.size(), 1u);  // The one in keyframe 2 went.
}

}  // namespace
}  // namespace dsm

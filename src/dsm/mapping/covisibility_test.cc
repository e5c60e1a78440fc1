// SPDX-License-Identifier: MIT
// Covisible keyframe selection on a hand-made map: a textured wall at z = 5 m seen by a newest
// keyframe whose own window covers the left half of the image.
#include "dsm/mapping/covisibility.h"

#include <gtest/gtest.h>

#include "dsm/mapping/projection.h"

namespace dsm {
namespace {

const PinholeCamera kCamera{640, 480, 400, 400, 319.5, 239.5};

// A keyframe at `centre` looking at the point `look_at` (world y down, as the camera's).
int AddKeyframe(Map* map, const Eigen::Vector3d& centre, const Eigen::Vector3d& look_at) {
  const Eigen::Vector3d z = (look_at - centre).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  Eigen::Matrix3d world_from_cam_rotation;
  world_from_cam_rotation << x, z.cross(x), z;
  auto kf = std::make_unique<Keyframe>();
  kf->cam_from_world = SE3d(SO3d(world_from_cam_rotation), centre).Inverse();
  return map->AddKeyframe(std::move(kf)).id;
}

// Points of the wall z = 5 with x in [x0, x1), hosted by `host`, 0.1 m apart.
void AddWallPoints(Map* map, int host, double x0, double x1) {
  for (double x = x0; x < x1; x += 0.1) {
    for (double y = -2.0; y <= 2.0; y += 0.1) {
      const Eigen::Vector3d p_host = map->keyframe(host).cam_from_world * Eigen::Vector3d(x, y, 5.0);
      if (p_host.z() <= 0) continue;
      Point p;
      p.host = host;
      p.pixel = kCamera.Project(p_host).cast<float>();
      p.idepth = static_cast<float>(1.0 / p_host.z());
      map->AddPoint(p);
    }
  }
}

TEST(Covisibility, ChoosesOldKeyframesThatFillDepletedAreas) {
  Map map;
  const int newest = AddKeyframe(&map, {0, 0, 0}, {0, 0, 5});
  const int right = AddKeyframe(&map, {0.2, 0, 0}, {0.2, 0, 5});     // Sees the empty right half.
  const int left = AddKeyframe(&map, {-0.2, 0, 0}, {-0.2, 0, 5});    // Sees only what is covered.
  const int oblique = AddKeyframe(&map, {12, 0, 0}, {1.5, 0, 5});    // The right half, 70 deg away.
  const int right_too = AddKeyframe(&map, {0.3, 0.1, 0}, {0.3, 0.1, 5});  // Same place as `right`.
  AddWallPoints(&map, newest, -3.0, 0.0);
  AddWallPoints(&map, right, 0.05, 3.0);
  AddWallPoints(&map, left, -3.0, -0.05);
  AddWallPoints(&map, oblique, 0.05, 3.0);
  AddWallPoints(&map, right_too, 0.0, 3.0);
  ASSERT_GT(ViewAngleDeg(map, kCamera, map.point(map.keyframe(oblique).points[0]), newest), 60.0);

  WindowOptions options;
  options.covisible_keyframes = 3;
  options.depleted_distance_px = 8.f;
  DistanceMap distance(kCamera.width, kCamera.height);
  for (int pid : map.keyframe(newest).points) {
    Eigen::Vector2f px;
    float rho;
    if (ProjectPoint(map, kCamera, map.point(pid), newest, 0.f, &px, &rho)) distance.Add(px);
  }
  const CovisibleSelection s = SelectCovisibleKeyframes(map, kCamera, {newest}, options, &distance);
  // `right` fills the empty half first; after it, `right_too` lands in covered areas only, `left`
  // always did, and `oblique` is seen from too different an angle.
  ASSERT_EQ(s.chosen.size(), 1u);
  EXPECT_EQ(s.chosen[0].keyframe, right);
  EXPECT_GT(s.chosen[0].depleted_points, 200);
  // The chosen keyframe's points now cover the right half.
  EXPECT_LT(distance.Distance({500.f, 240.f}), 8.f);
  // The unchosen keyframes' points that pass the angle and scale tests mark mapped places.
  int expected_other = 0;
  for (int k : {left, right_too})
    for (int pid : map.keyframe(k).points) {
      Eigen::Vector2f px;
      float rho;
      expected_other += ProjectPoint(map, kCamera, map.point(pid), newest, 0.f, &px, &rho);
    }
  EXPECT_EQ(static_cast<int>(s.other_old_pixels.size()), expected_other);

  // DSM-SW: no covisible part.
  options.covisible_keyframes = 0;
  EXPECT_TRUE(SelectCovisibleKeyframes(map, kCamera, {newest}, options, &distance).chosen.empty());
}

TEST(Covisibility, ViewAngleAtThePoint) {
  Map map;
  const int a = AddKeyframe(&map, {0, 0, 0}, {0, 0, 5});
  const int b = AddKeyframe(&map, {5, 0, 5}, {0, 0, 5});
  AddWallPoints(&map, a, 0.0, 0.05);  // One column at x = 0.
  const Point& p = map.point(map.keyframe(a).points[20]);  // y = 0: the point (0, 0, 5).
  EXPECT_NEAR(ViewAngleDeg(map, kCamera, p, a), 0.0, 1e-6);
  EXPECT_NEAR(ViewAngleDeg(map, kCamera, p, b), 90.0, 1e-3);
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/geometry/sim3_ransac.h"

#include <random>

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(Sim3Ransac, FindsTheSimilarityAmongOutliers) {
  PinholeCamera camera;
  camera.width = 640, camera.height = 480, camera.fx = camera.fy = 384, camera.cx = 319.5, camera.cy = 239.5;
  const Sim3d truth(0.6, SO3d::Exp(Eigen::Vector3d(0.05, -0.2, 0.1)), Eigen::Vector3d(0.3, -0.1, 0.2));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d x(2.0 * u(rng), 1.5 * u(rng), 3.0 + 1.5 * u(rng));
    a.push_back(x);
    // 60% outliers: points somewhere else in view.
    b.push_back(i % 5 < 2 ? truth * x : Eigen::Vector3d(u(rng), u(rng), 2.0 + u(rng)));
  }
  const Sim3RansacResult r = EstimateSim3Ransac(a, b, camera, {});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.inliers.size(), 80u);
  EXPECT_NEAR(r.b_from_a.Scale(), 0.6, 1e-6);
  EXPECT_LT((r.b_from_a.Translation() - truth.Translation()).norm(), 1e-6);
  EXPECT_LT((r.b_from_a.So3().Inverse() * truth.So3()).Log().norm(), 1e-6);
  // Too few consistent matches: no similarity.
  const std::vector<Eigen::Vector3d> few_a(a.begin(), a.begin() + 30), few_b(b.begin(), b.begin() + 30);
  EXPECT_FALSE(EstimateSim3Ransac(few_a, few_b, camera, {}).ok);
}

}  // namespace
}  // namespace dsm

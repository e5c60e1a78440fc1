// SPDX-License-Identifier: MIT
#include "dsm/tracking/two_view.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "dsm/lie/so3.h"
#include "dsm/testing/motion_error.h"

namespace dsm {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Scene {
  TwoViewProblem problem;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;  // unit
  std::vector<double> idepth;   // truth, for |t| = 1
};

// Points 1-4 m in front of a 640x480 camera (f = 450), a 4 cm step sideways and a little forward
// with a 1 degree turn: the small-baseline start of a hand-held camera. Tracks get Gaussian noise
// of `noise_px`, and every tenth one is replaced by a wrong match up to 15 px away.
Scene MakeScene(double noise_px, bool outliers, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  Scene s;
  s.problem.fx = s.problem.fy = 450.0;
  s.rotation = SO3d::Exp(Eigen::Vector3d(0.2, -0.9, 0.3) * kDeg).Matrix();
  const Eigen::Vector3d t_metric(0.035, 0.008, 0.015);  // current_from_reference, metres
  s.translation = t_metric.normalized();
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d x(u(rng) * 320 / 450.0, u(rng) * 240 / 450.0);
    const double depth = 2.5 + 1.5 * u(rng);
    const Eigen::Vector3d p = s.rotation * (Eigen::Vector3d(x.homogeneous()) * depth) + t_metric;
    Eigen::Vector2d m = p.hnormalized() + Eigen::Vector2d(noise(rng), noise(rng)) / 450.0;
    if (outliers && i % 10 == 0) m += Eigen::Vector2d(u(rng), u(rng)) * 15.0 / 450.0;
    s.problem.reference.push_back(x);
    s.problem.current.push_back(m);
    s.idepth.push_back(t_metric.norm() / depth);
  }
  return s;
}

using testing::DirectionErrorDeg;

double RotationErrorDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return testing::RotationErrorDeg(SO3d(a), SO3d(b)); }

TEST(TwoView, ExactTracksGiveTheExactMotionFromAFarStart) {
  const Scene s = MakeScene(0.0, false, 1);
  // Start 0.5 deg off in rotation and about 10 deg off in direction.
  const Eigen::Matrix3d R0 = SO3d::Exp(Eigen::Vector3d(0.3, 0.3, -0.2) * kDeg).Matrix() * s.rotation;
  const Eigen::Vector3d t0 = (s.translation + Eigen::Vector3d(0.0, 0.12, -0.12)).normalized();
  ASSERT_GT(DirectionErrorDeg(t0, s.translation), 9.0);
  const TwoViewResult r = RefineTwoView(s.problem, R0, t0);
  EXPECT_LT(DirectionErrorDeg(r.translation, s.translation), 1e-3);
  EXPECT_LT(RotationErrorDeg(r.rotation, s.rotation), 1e-4);
  EXPECT_NEAR(r.translation.norm(), 1.0, 1e-12);
  EXPECT_LT(r.final_cost, 1e-8);
  ASSERT_EQ(r.idepth.size(), s.idepth.size());
  for (size_t i = 0; i < s.idepth.size(); ++i) EXPECT_NEAR(r.idepth[i] / s.idepth[i], 1.0, 1e-4) << i;
}

TEST(TwoView, NoisyTracksWithWrongMatchesStillGiveTheMotion) {
  // Over several draws: 0.3 px noise and 10 % wrong matches, from a start as far off as a minimal
  // sample leaves it (7 deg in direction, 0.46 deg in rotation). With this noise alone the least-
  // squares motion scatters by 0.1-0.8 deg in direction and 0.04 deg in rotation; the wrong matches
  // must not add to that.
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Scene s = MakeScene(0.3, true, seed);
    const Eigen::Matrix3d R0 = SO3d::Exp(Eigen::Vector3d(-0.2, 0.4, 0.1) * kDeg).Matrix() * s.rotation;
    const Eigen::Vector3d t0 = (s.translation + Eigen::Vector3d(0.05, -0.1, 0.05)).normalized();
    const TwoViewResult r = RefineTwoView(s.problem, R0, t0);
    EXPECT_LT(r.final_cost, r.initial_cost) << seed;
    EXPECT_LT(DirectionErrorDeg(r.translation, s.translation), 1.5) << seed;
    EXPECT_LT(RotationErrorDeg(r.rotation, s.rotation), 0.05) << seed;
  }
}

TEST(TwoViewDeathTest, RefusesMismatchedTracks) {
  TwoViewProblem p;
  p.reference.resize(3);
  p.current.resize(2);
  EXPECT_DEATH(RefineTwoView(p, Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitX()), "matched tracks");
}

}  // namespace
}  // namespace dsm

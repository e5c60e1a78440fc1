// SPDX-License-Identifier: MIT
#include "dsm/eval/metrics.h"

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

Trajectory Circle(int n, int64_t t0_ns, int64_t dt_ns) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    const double a = 0.1 * i;
    Eigen::Matrix<double, 6, 1> xi;
    xi << std::cos(a), std::sin(a), 0.1 * a, 0.0, 0.0, a;
    const SE3d pose = SE3d::Exp(xi);
    t.Add(t0_ns + i * dt_ns, SE3d(pose.So3(), Eigen::Vector3d(std::cos(a), std::sin(a), 0.1 * a)));
  }
  return t;
}

TEST(Stats, MatchesHandComputedValues) {
  const ErrorStats s = ComputeStats({1, 2, 3, 4});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_DOUBLE_EQ(ComputeStats({5, 1, 3}).median, 3);
  EXPECT_THROW(ComputeStats({}), InputError);
}

TEST(Evaluate, Sim3AlignmentRemovesASimilarity) {
  const Trajectory ref = Circle(50, 1000, 50000000);
  Sim3d::Tangent xi;
  xi << 1, 2, 3, 0.1, 0.2, 0.3, std::log(0.4);
  const Sim3d S = Sim3d::Exp(xi);
  Trajectory est;
  for (size_t i = 0; i < ref.size(); ++i) {
    est.Add(ref.stamps_ns[i] + 3000000, SE3d(S.So3() * ref.poses[i].So3(), S * ref.poses[i].Translation()));
  }
  EvalOptions opt;
  opt.align = Alignment::kSim3;
  opt.rpe_delta = 5;
  const EvalResult r = Evaluate(ref, est, opt);
  EXPECT_EQ(r.pairs, 50u);
  EXPECT_LT(r.ape.rmse, 1e-9);
  EXPECT_NEAR(r.ref_from_est.Scale(), 1.0 / 0.4, 1e-9);
  ASSERT_TRUE(r.rpe.has_value());
  EXPECT_EQ(r.rpe->count, 9u);  // indices 0, 5, ..., 45
  EXPECT_LT(r.rpe->rmse, 1e-9);
  // SE(3) cannot undo the scale.
  opt.align = Alignment::kSE3;
  EXPECT_GT(Evaluate(ref, est, opt).ape.rmse, 0.1);
}

// The reference drawn in the estimate's frame lands on the estimate, with the estimate's stamps.
TEST(Evaluate, ReferenceInEstimateFrameUndoesTheAlignment) {
  const Trajectory ref = Circle(30, 1000, 50000000);
  Sim3d::Tangent xi;
  xi << -1, 0.5, 2, 0.3, -0.2, 0.1, std::log(2.5);
  const Sim3d S = Sim3d::Exp(xi);
  Trajectory est;
  for (size_t i = 0; i < ref.size(); i += 2) {  // Every other pose, 2 ms later.
    est.Add(ref.stamps_ns[i] + 2000000, SE3d(S.So3() * ref.poses[i].So3(), S * ref.poses[i].Translation()));
  }
  EvalOptions opt;
  opt.align = Alignment::kSim3;
  const Trajectory in_est = ReferenceInEstimateFrame(ref, est, Evaluate(ref, est, opt), opt);
  ASSERT_EQ(in_est.size(), est.size());
  for (size_t k = 0; k < est.size(); ++k) {
    EXPECT_EQ(in_est.stamps_ns[k], est.stamps_ns[k]);
    EXPECT_LT((in_est.poses[k].Translation() - est.poses[k].Translation()).norm(), 1e-9) << k;
    EXPECT_LT((in_est.poses[k].So3().Matrix() - est.poses[k].So3().Matrix()).norm(), 1e-9) << k;
  }
}

TEST(Evaluate, ApeOfAKnownOffset) {
  const Trajectory ref = Circle(20, 0, 100000000);
  Trajectory est = ref;
  for (auto& p : est.poses) p.SetTranslation(p.Translation() + Eigen::Vector3d(0, 0, 0.5));
  EvalOptions opt;
  const EvalResult r = Evaluate(ref, est, opt);
  EXPECT_NEAR(r.ape.rmse, 0.5, 1e-12);
  EXPECT_NEAR(r.ape.std, 0.0, 1e-12);
  EXPECT_EQ(r.ref_from_est.Scale(), 1.0);
}

TEST(Association, NearestWithinToleranceFromTheShorterTrajectory) {
  Trajectory ref, est;
  for (int i = 0; i < 10; ++i) ref.Add(i * 100000000LL, SE3d());  // 10 Hz
  est.Add(140000000LL, SE3d());   // nearest 100 ms (40 ms away) > 10 ms: dropped
  est.Add(205000000LL, SE3d());   // 200 ms, 5 ms away
  est.Add(310000000LL, SE3d());   // 300 ms, exactly 10 ms: kept
  const Association a = AssociateByTime(ref, est, 0.01);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a.ref_index[0], 2u);
  EXPECT_EQ(a.est_index[0], 1u);
  EXPECT_EQ(a.ref_index[1], 3u);
}

TEST(Association, UnstampedNeedsEqualSizes) {
  Trajectory a, b;
  a.poses.resize(3);
  b.poses.resize(4);
  EXPECT_THROW(AssociateByIndex(a, b, "ref.txt", "est.txt"), InputError);
  EXPECT_THROW(Evaluate(a, Trajectory{}, EvalOptions{}), InputError);
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// The evaluator reproduces the reference values of the field's standard tool on the shared
// golden trajectories (../shared/data/README.md), to 1e-6 relative.
#include <gtest/gtest.h>

#include "dsm/eval/metrics.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

Trajectory Load(const std::string& name) {
  const auto path = testing::SharedDataDir() / "trajectories" / name;
  return ReadTrajectory(path, DetectTrajectoryFormat(path));
}

void ExpectRel(double actual, double expected, const char* what) {
  EXPECT_NEAR(actual, expected, 1e-6 * std::abs(expected)) << what;
}

TEST(GoldenEval, KittiApeSe3) {
  EvalOptions options;
  options.align = Alignment::kSE3;
  const EvalResult r = Evaluate(Load("KITTI_00_gt.txt"), Load("KITTI_00_ORB.txt"), options);
  EXPECT_EQ(r.pairs, 4541u);
  ExpectRel(r.ape.rmse, 1.3034497145650266, "rmse");
  ExpectRel(r.ape.mean, 1.1569971285389768, "mean");
  ExpectRel(r.ape.median, 1.065624769555848, "median");
  ExpectRel(r.ape.std, 0.6002822693968323, "std");
  ExpectRel(r.ape.min, 0.06931322021483087, "min");
  ExpectRel(r.ape.max, 3.587949120678954, "max");
}

TEST(GoldenEval, KittiRpeTenMetresAlongTheEstimate) {
  EvalOptions options;
  options.rpe_delta = 10.0;
  options.rpe_unit = RpeUnit::kMeters;
  const EvalResult r = Evaluate(Load("KITTI_00_gt.txt"), Load("KITTI_00_ORB.txt"), options);
  ASSERT_TRUE(r.rpe.has_value());
  ExpectRel(r.rpe->rmse, 0.22626134329310163, "rmse");
  ExpectRel(r.rpe->mean, 0.16901737200653275, "mean");
  ExpectRel(r.rpe->max, 1.2722090778658726, "max");
}

TEST(GoldenEval, Fr2DeskTimestampAssociationAndSe3) {
  EvalOptions options;
  options.align = Alignment::kSE3;
  options.max_dt_s = 0.01;
  const EvalResult r = Evaluate(Load("fr2_desk_groundtruth.txt"), Load("fr2_desk_ORB.txt"), options);
  EXPECT_EQ(r.pairs, 2174u);
  // The reference values are given to six decimals.
  EXPECT_NEAR(r.ape.rmse, 0.008119, 5e-7);
  EXPECT_NEAR(r.ape.max, 0.024300, 5e-7);
  EXPECT_NEAR(r.ape.mean, 0.007492, 5e-7);
  EXPECT_NEAR(r.ape.median, 0.007415, 5e-7);
}

TEST(GoldenEval, MonocularKeyframesNeedSim3) {
  // A monocular keyframe trajectory has arbitrary scale: Sim(3) recovers it, SE(3) cannot.
  EvalOptions options;
  options.align = Alignment::kSim3;
  const Trajectory gt = Load("freiburg1_xyz-groundtruth.txt");
  const Trajectory est = Load("freiburg1_xyz-ORB_kf_mono.txt");
  const EvalResult sim3 = Evaluate(gt, est, options);
  options.align = Alignment::kSE3;
  const EvalResult se3 = Evaluate(gt, est, options);
  EXPECT_NE(sim3.ref_from_est.Scale(), 1.0);
  EXPECT_LT(sim3.ape.rmse, 0.05);
  EXPECT_LT(sim3.ape.rmse, se3.ape.rmse);
}

TEST(GoldenEval, EurocCsvGroundTruthAgainstTumEstimate) {
  EvalOptions options;
  options.align = Alignment::kSim3;
  const EvalResult r = Evaluate(Load("V102_groundtruth.csv"), Load("V102.txt"), options);
  EXPECT_GT(r.pairs, 500u);
  EXPECT_LT(r.ape.rmse, 0.2);
}

}  // namespace
}  // namespace dsm

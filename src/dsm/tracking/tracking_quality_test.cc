// SPDX-License-Identifier: MIT
#include "dsm/tracking/tracking_quality.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

TrackResult Tracked(double p50, double inliers = 0.9) {
  TrackResult r;
  r.ok = true;
  r.residual_p50 = p50;
  r.inlier_ratio = inliers;
  return r;
}

SE3d Turned(double deg, double tx = 0.0) {
  Eigen::Matrix<double, 6, 1> xi = Eigen::Matrix<double, 6, 1>::Zero();
  xi(0) = tx;
  xi(4) = deg * M_PI / 180.0;
  return SE3d::Exp(xi);
}

TEST(TrackingQuality, JudgesAgainstTheRunningLevels) {
  QualityOptions o;
  o.history = 5;
  TrackingQuality q(o);
  // Before `min_history` (3) trusted frames only the absolute rules apply.
  EXPECT_EQ(q.CheckImage(0.0), "");
  EXPECT_EQ(q.CheckTracking(Tracked(100.0), SE3d(), 1, 1.0), "");
  for (double p50 : {2.0, 2.2, 1.8, 2.1, 1.9}) q.Trust(p50, 10.0);
  EXPECT_DOUBLE_EQ(q.ResidualLevel(), 2.0);
  EXPECT_DOUBLE_EQ(q.TextureLevel(), 10.0);
  EXPECT_EQ(q.CheckImage(5.0), "");
  EXPECT_NE(q.CheckImage(3.0).find("too little texture"), std::string::npos);
  EXPECT_NE(q.CheckImage(std::nan("")), "");
  EXPECT_EQ(q.CheckTracking(Tracked(7.9), SE3d(), 1, 1.0), "");
  EXPECT_NE(q.CheckTracking(Tracked(8.1), SE3d(), 1, 1.0).find("median residual"), std::string::npos);
  // Relocalised against another keyframe than the last reference: 6 x the level.
  EXPECT_EQ(q.CheckTracking(Tracked(11.9), SE3d(), 1, 1.0, /*other_keyframe=*/true), "");
  EXPECT_NE(q.CheckTracking(Tracked(12.1), SE3d(), 1, 1.0, true).find("median residual"), std::string::npos);
  EXPECT_NE(q.CheckTracking(Tracked(2.0, 0.4), SE3d(), 1, 1.0).find("inliers"), std::string::npos);
  TrackResult failed;
  failed.reason = "diverged";
  EXPECT_EQ(q.CheckTracking(failed, SE3d(), 1, 1.0), "diverged");
  // Motion: 25 deg per frame, parallax 1.5 against the reference.
  EXPECT_EQ(q.CheckTracking(Tracked(2.0), Turned(20.0), 1, 1.0), "");
  EXPECT_NE(q.CheckTracking(Tracked(2.0), Turned(30.0), 1, 1.0).find("implausible motion"), std::string::npos);
  EXPECT_EQ(q.CheckTracking(Tracked(2.0), Turned(30.0), 2, 1.0), "");
  TrackResult far = Tracked(2.0);
  far.frame_from_keyframe = Turned(0.0, 2.0);
  EXPECT_NE(q.CheckTracking(far, SE3d(), 1, 1.0).find("parallax"), std::string::npos);
  EXPECT_EQ(q.CheckTracking(far, SE3d(), 1, 0.5), "");
}

// The levels judge from min_history values on; a new map's are seeded before its first trusted
// frame, so that a black or noise frame right after the start is lost like any other.
TEST(TrackingQuality, JudgesFromTheSeedOfANewMap) {
  QualityOptions o;
  o.history = 20;
  TrackingQuality warming(o);
  warming.Trust(2.0, 10.0);
  warming.Trust(2.0, 10.0);
  EXPECT_EQ(warming.CheckImage(0.0), "");
  warming.Trust(2.0, 10.0);
  EXPECT_NE(warming.CheckImage(0.0).find("too little texture"), std::string::npos);

  TrackingQuality q(o);
  q.Seed(1.5, {12.0, 11.0, 12.5, std::nan("")});
  EXPECT_DOUBLE_EQ(q.ResidualLevel(), 1.5);
  EXPECT_DOUBLE_EQ(q.TextureLevel(), 12.0);
  EXPECT_NE(q.CheckImage(0.0).find("too little texture"), std::string::npos);  // Black.
  EXPECT_EQ(q.CheckImage(11.0), "");
  EXPECT_NE(q.CheckTracking(Tracked(40.0), SE3d(), 1, 1.0).find("median residual"), std::string::npos);  // Noise.
  EXPECT_EQ(q.CheckTracking(Tracked(5.9), SE3d(), 1, 1.0), "");
  // Trusted frames move the levels on from the seed.
  for (int i = 0; i < 5; ++i) q.Trust(3.0, 8.0);
  EXPECT_DOUBLE_EQ(q.ResidualLevel(), 3.0);
  EXPECT_DOUBLE_EQ(q.TextureLevel(), 8.0);
  // Without a residual (the tracking failed) only the texture is seeded.
  TrackingQuality textures_only(o);
  textures_only.Seed(0.0, {12.0, 12.0, 12.0});
  EXPECT_NE(textures_only.CheckImage(1.0), "");
  EXPECT_EQ(textures_only.CheckTracking(Tracked(40.0), SE3d(), 1, 1.0), "");
}

TEST(TrackingQuality, BoundsTheJumpOfARelocalisation) {
  TrackingQuality q{QualityOptions{}};
  // Reach per frame: 2 x speed + 0.02 x mean depth; 10 frames at speed 0.01, depth 1: 0.4.
  EXPECT_EQ(q.CheckJump(Turned(0.0, 0.39), 10, Turned(0.0, 0.01), 1.0), "");
  EXPECT_NE(q.CheckJump(Turned(0.0, 0.41), 10, Turned(0.0, 0.01), 1.0).find("implausible jump"), std::string::npos);
  EXPECT_EQ(q.CheckJump(Turned(0.0, 0.41), 11, Turned(0.0, 0.01), 1.0), "");
  // The turn: at most 2.5 deg per frame off the constant-velocity prediction; 15 frames turning
  // 1.5 deg each are predicted at 22.5 deg, give or take 37.5.
  EXPECT_EQ(q.CheckJump(Turned(59.0), 15, Turned(1.5), 1.0), "");
  EXPECT_EQ(q.CheckJump(Turned(-14.0), 15, Turned(1.5), 1.0), "");
  EXPECT_NE(q.CheckJump(Turned(61.0), 15, Turned(1.5), 1.0).find("implausible turn (38 deg off the prediction, reach 38 deg)"),
            std::string::npos) << q.CheckJump(Turned(61.0), 15, Turned(1.5), 1.0);
  EXPECT_NE(q.CheckJump(Turned(-16.0), 15, Turned(1.5), 1.0).find("implausible turn"), std::string::npos);
}

TEST(TrackingQuality, CheckSpeedIsTheJumpsReachAlone) {
  TrackingQuality q{QualityOptions{}};
  // 3 frames at speed 0.05, depth 2: 3 x (2 x 0.05 + 0.02 / 0.5) = 0.42, whatever the turn.
  EXPECT_EQ(q.CheckSpeed(Turned(90.0, 0.41), 3, 0.05, 0.5), "");
  EXPECT_NE(q.CheckSpeed(Turned(0.0, 0.43), 3, 0.05, 0.5).find("implausible jump"), std::string::npos);
  EXPECT_NE(q.CheckJump(Turned(90.0, 0.41), 3, Turned(0.0, 0.05), 0.5).find("implausible turn"), std::string::npos);
}

TEST(TrackingQuality, OnlyAFrameWithTheUsualTextureRelocalises) {
  QualityOptions o;
  o.history = 3;
  TrackingQuality q(o);
  EXPECT_EQ(q.CheckRelocalisationImage(1.0), "");  // No level yet.
  for (int i = 0; i < 3; ++i) q.Trust(1.0, 10.0);
  EXPECT_EQ(q.CheckImage(5.0), "");
  EXPECT_EQ(q.CheckRelocalisationImage(6.9), "less texture than usual (6.90, usual 10.00)");
  EXPECT_EQ(q.CheckRelocalisationImage(7.1), "");
  // The newest keyframe, made where the view had turned plainer, lowers the level; a richer one
  // does not raise it.
  EXPECT_EQ(q.CheckRelocalisationImage(5.0, 8.0), "less texture than usual (5.00, usual 8.00)");
  EXPECT_EQ(q.CheckRelocalisationImage(6.9, 8.0), "");
  EXPECT_EQ(q.CheckRelocalisationImage(6.9, 12.0), "less texture than usual (6.90, usual 10.00)");
  o.min_relocalisation_texture_ratio = 0.3;  // Below min_texture_ratio.
  EXPECT_THROW(o.Validate(), InputError);
}

// The inlier level follows the trusted frames whose inlier share is known; a relocalisation
// restarts the residual level, not it.
TEST(TrackingQuality, KeepsTheInlierLevelOfTrackedFrames) {
  QualityOptions o;
  o.history = 5;
  TrackingQuality q(o);
  q.Trust(1.0, 10.0, 0.9);
  q.Trust(1.0, 10.0, 0.8);
  EXPECT_EQ(q.InlierLevel(), 0.0);  // Fewer than min_history (3) values.
  q.Trust(1.0, 10.0);               // Not known: no value.
  EXPECT_EQ(q.InlierLevel(), 0.0);
  for (double inliers : {0.7, 0.95, 0.92, 0.93}) q.Trust(1.0, 10.0, inliers);
  EXPECT_DOUBLE_EQ(q.InlierLevel(), 0.92);  // Of the last 5: 0.8, 0.7, 0.95, 0.92, 0.93.
  q.Restart(3.0, 10.0);
  EXPECT_DOUBLE_EQ(q.InlierLevel(), 0.92);
}

TEST(TrackingQuality, NoKeyframeWhereTheTextureJustFell) {
  TrackingQuality q{QualityOptions{}};
  EXPECT_TRUE(q.CheckKeyframeImage(8.1, 10.0));
  EXPECT_FALSE(q.CheckKeyframeImage(7.9, 10.0));
  EXPECT_TRUE(q.CheckKeyframeImage(7.9, 7.9));  // It fell for good: the next frame may.
  EXPECT_TRUE(q.CheckKeyframeImage(1.0, 0.0));  // The first frame.
}

TEST(TrackingQuality, RestartsTheResidualLevelAtARelocalisedFrame) {
  QualityOptions o;
  o.history = 3;
  TrackingQuality q(o);
  for (int i = 0; i < 3; ++i) q.Trust(1.0, 10.0);
  q.Restart(3.0, 10.0);
  EXPECT_DOUBLE_EQ(q.ResidualLevel(), 3.0);
  EXPECT_EQ(q.CheckTracking(Tracked(11.0), SE3d(), 1, 1.0), "");
  q.Restart(0.5, 10.0);  // Never below the old level.
  EXPECT_DOUBLE_EQ(q.ResidualLevel(), 3.0);
}

TEST(TrackingQuality, RejectsBadOptions) {
  QualityOptions o;
  o.max_residual_ratio = 1.0;
  EXPECT_THROW(TrackingQuality{o}, InputError);
  o = QualityOptions();
  o.history = 0;
  EXPECT_THROW(TrackingQuality{o}, InputError);
  o = QualityOptions();
  o.history = QualityOptions::min_history - 1;
  EXPECT_THROW(TrackingQuality{o}, InputError);
}

}  // namespace
}  // namespace dsm

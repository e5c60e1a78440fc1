// SPDX-License-Identifier: MIT
// The feature-based guess recovers a pose far outside direct alignment's basin (a fifth of a lap
// of `loop` between the two frames), and direct alignment from it lands on the truth.
#include "dsm/tracking/feature_pose.h"

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>

#include "dsm/synth/renderer.h"

namespace dsm {
namespace {

TEST(FeaturePose, RecoversALargeOffsetThatDirectAlignmentMisses) {
  synth::SynthOptions options;
  options.scene = "loop";
  const synth::SynthSequence seq = synth::MakeSequence(options);
  const int ref = 100, cur = 118;
  synth::FormationOptions formation;
  formation.noise_sigma = 1.0;
  synth::RenderedFrame a = synth::RenderSequenceFrame(seq, ref, formation);
  synth::RenderedFrame b = synth::RenderSequenceFrame(seq, cur, formation);
  const ImagePyramid pa(a.image, 5), pb(b.image, 5);
  // Map points: strong gradients of the reference with their rendered depth.
  std::vector<ReferencePoint> points;
  for (int y = 8; y < pa.height(0) - 8; y += 4)
    for (int x = 8; x < pa.width(0) - 8; x += 4) {
      const PixelGrad g = pa.At(0, x, y);
      if (g[1] * g[1] + g[2] * g[2] > 100.f && a.depth(x, y) > 0.f)
        points.push_back({Eigen::Vector2f(x, y), 1.f / a.depth(x, y)});
    }
  ASSERT_GT(points.size(), 1000u);
  const SE3d truth = seq.world_from_cam[cur].Inverse() * seq.world_from_cam[ref];
  ASSERT_GT(truth.So3().Log().norm() * 180 / M_PI, 15.0);  // A large turn between the two.

  const FeaturePoseOptions fo;
  const FeaturePose pose = EstimateFeaturePose(DetectOrbFeatures(pb, fo), DetectOrbFeatures(pa, fo), points, seq.camera, fo);
  ASSERT_TRUE(pose.ok) << pose.matches << " matches, " << pose.inliers << " inliers";
  EXPECT_GE(pose.inliers, 50);
  SE3d err = pose.frame_from_keyframe * truth.Inverse();
  EXPECT_LT(err.So3().Log().norm() * 180 / M_PI, 1.0);
  EXPECT_LT(err.Translation().norm(), 0.03);

  TrackerOptions to;
  to.levels = 5;
  to.iterations = {10, 20, 50, 75, 75};
  FrameTracker tracker(to);
  tracker.SetReference(&pa, seq.camera, points);
  const TrackResult from_identity = tracker.Track(pb, SE3d(), 0.0, 0.0);
  const double identity_err = (from_identity.frame_from_keyframe * truth.Inverse()).So3().Log().norm() * 180 / M_PI;
  EXPECT_GT(identity_err, 1.0);  // Direct alignment alone converges elsewhere.
  const TrackResult refined = tracker.Track(pb, pose.frame_from_keyframe, 0.0, 0.0);
  ASSERT_TRUE(refined.ok) << refined.reason;
  err = refined.frame_from_keyframe * truth.Inverse();
  EXPECT_LT(err.So3().Log().norm() * 180 / M_PI, 0.1);
  EXPECT_LT(err.Translation().norm(), 0.005);
}

// The count that ranks relocalisation candidates is the number of matches of OpenCV's brute-force
// matcher that pass the ratio test, on real features of two views and on descriptor sets with
// exact ties and single rows.
TEST(FeaturePose, CountsTheRatioMatchesOfTheBruteForceMatcher) {
  synth::SynthOptions options;
  options.scene = "loop";
  const synth::SynthSequence seq = synth::MakeSequence(options);
  synth::FormationOptions formation;
  formation.noise_sigma = 1.0;
  const ImagePyramid pa(synth::RenderSequenceFrame(seq, 100, formation).image, 5);
  const ImagePyramid pb(synth::RenderSequenceFrame(seq, 106, formation).image, 5);
  const FeaturePoseOptions fo;
  const OrbFeatures a = DetectOrbFeatures(pa, fo), b = DetectOrbFeatures(pb, fo);
  ASSERT_GT(a.descriptors.rows, 500);
  ASSERT_GT(b.descriptors.rows, 500);
  const auto brute_force = [](const OrbFeatures& x, const OrbFeatures& y, double ratio) {
    std::vector<std::vector<cv::DMatch>> knn;
    cv::BFMatcher(cv::NORM_HAMMING).knnMatch(x.descriptors, y.descriptors, knn, 2);
    int n = 0;
    for (const auto& m : knn) n += m.size() == 2 && m[0].distance <= ratio * m[1].distance;
    return n;
  };
  const int expected = brute_force(b, a, fo.ratio);
  EXPECT_GT(expected, 100);  // Six frames apart: many true matches.
  EXPECT_EQ(CountFeatureMatches(b, a, fo), expected);
  EXPECT_EQ(CountFeatureMatches(a, b, fo), brute_force(a, b, fo.ratio));

  // Ties: every keyframe descriptor twice (nearest and second nearest equal: no match passes
  // unless the distance is 0), and a keyframe of one descriptor (no second nearest).
  OrbFeatures doubled;
  cv::vconcat(a.descriptors, a.descriptors, doubled.descriptors);
  EXPECT_EQ(CountFeatureMatches(b, doubled, fo), brute_force(b, doubled, fo.ratio));
  EXPECT_EQ(CountFeatureMatches(a, doubled, fo), brute_force(a, doubled, fo.ratio));
  EXPECT_EQ(CountFeatureMatches(a, doubled, fo), a.descriptors.rows);  // Each finds itself twice at 0.
  OrbFeatures single;
  single.descriptors = a.descriptors.row(0).clone();
  EXPECT_EQ(CountFeatureMatches(b, single, fo), 0);
  EXPECT_EQ(CountFeatureMatches(b, OrbFeatures{}, fo), 0);
}

}  // namespace
}  // namespace dsm

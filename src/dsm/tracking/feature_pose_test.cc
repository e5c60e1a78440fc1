// SPDX-License-Identifier: MIT
// The feature-based guess recovers a pose far outside direct alignment's basin (a fifth of a lap
// of `loop` between the two frames), and direct alignment from it lands on the truth.
#include "dsm/tracking/feature_pose.h"

#include <gtest/gtest.h>

#include "dsm/synth/renderer.h"

namespace dsm {
namespace {

// Two frames of `loop` a fifth of a lap apart, and map points of the first: its strong gradients
// with their rendered depth.
struct TwoViews {
  TwoViews() {
    synth::SynthOptions options;
    options.scene = "loop";
    seq = synth::MakeSequence(options);
    const int ref = 100, cur = 118;
    synth::FormationOptions formation;
    formation.noise_sigma = 1.0;
    a = synth::RenderSequenceFrame(seq, ref, formation);
    b = synth::RenderSequenceFrame(seq, cur, formation);
    const ImagePyramid pa(a.image, 5);
    for (int y = 8; y < pa.height(0) - 8; y += 4)
      for (int x = 8; x < pa.width(0) - 8; x += 4) {
        const PixelGrad g = pa.At(0, x, y);
        if (g[1] * g[1] + g[2] * g[2] > 100.f && a.depth(x, y) > 0.f)
          points.push_back({Eigen::Vector2f(x, y), 1.f / a.depth(x, y)});
      }
    truth = seq.world_from_cam[cur].Inverse() * seq.world_from_cam[ref];
  }
  synth::SynthSequence seq;
  synth::RenderedFrame a, b;
  std::vector<ReferencePoint> points;
  SE3d truth;  // b_from_a
};

// A guess within direct alignment's basin: 1 degree and 0.03 of the truth.
void ExpectGoodGuess(const FeaturePose& pose, const SE3d& truth) {
  ASSERT_TRUE(pose.ok) << pose.matches << " matches, " << pose.inliers << " inliers";
  EXPECT_GE(pose.inliers, 50);
  const SE3d err = pose.frame_from_keyframe * truth.Inverse();
  EXPECT_LT(err.So3().Log().norm() * 180 / M_PI, 1.0);
  EXPECT_LT(err.Translation().norm(), 0.03);
}

TEST(FeaturePose, RecoversALargeOffsetThatDirectAlignmentMisses) {
  const TwoViews views;
  const SE3d& truth = views.truth;
  const ImagePyramid pa(views.a.image, 5), pb(views.b.image, 5);
  const std::vector<ReferencePoint>& points = views.points;
  const synth::SynthSequence& seq = views.seq;
  ASSERT_GT(points.size(), 1000u);
  ASSERT_GT(truth.So3().Log().norm() * 180 / M_PI, 15.0);  // A large turn between the two.

  const FeaturePoseOptions fo;
  const OrbFeatures fb = DetectOrbFeatures(pb, fo), fa = DetectOrbFeatures(pa, fo);
  const FeaturePose pose = EstimateFeaturePose(fb, fa, points, seq.camera, fo);
  ExpectGoodGuess(pose, truth);
  // From the caller's matches (relocalisation ranks keyframes by them first): the same pose.
  const FeaturePose from_matches = EstimateFeaturePose(fb, fa, MatchFeatures(fb, fa, fo), points, seq.camera, fo);
  EXPECT_EQ(from_matches.matches, pose.matches);
  EXPECT_EQ(from_matches.inliers, pose.inliers);
  EXPECT_TRUE(from_matches.frame_from_keyframe.Matrix().isApprox(pose.frame_from_keyframe.Matrix(), 1e-12));

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
  const SE3d err = refined.frame_from_keyframe * truth.Inverse();
  EXPECT_LT(err.So3().Log().norm() * 180 / M_PI, 0.1);
  EXPECT_LT(err.Translation().norm(), 0.005);
}

// A dim, low-contrast view of the place (a fifth of the contrast, as after dark frames or a short
// exposure, with the render noise on top) is matched as the bright one is: features are detected
// at a fixed contrast. At its own grey levels FAST finds almost no corners in it.
TEST(FeaturePose, ADimViewFindsThePoseAsABrightOne) {
  TwoViews views;
  Image<float>& dim = views.b.image;
  for (int y = 0; y < dim.height(); ++y)
    for (int x = 0; x < dim.width(); ++x) dim(x, y) = 30.f + 0.2f * dim(x, y) + ((x * 7 + y * 13) % 5 - 2) * 0.5f;
  const ImagePyramid pa(views.a.image, 5), pb(dim, 5);
  const FeaturePoseOptions fo;
  const OrbFeatures features = DetectOrbFeatures(pb, fo);
  EXPECT_GE(features.keypoints.size(), 900u);
  ExpectGoodGuess(EstimateFeaturePose(features, DetectOrbFeatures(pa, fo), views.points, views.seq.camera, fo),
                  views.truth);
  // A uniform image has no features (and no division by its zero deviation).
  const Image<float> flat(dim.width(), dim.height(), 50.f);
  EXPECT_TRUE(DetectOrbFeatures(ImagePyramid(flat, 5), fo).keypoints.empty());
}

// Matching equals OpenCV's brute-force k-nearest matcher with the ratio test (the same pairs, the
// first of equally near descriptors taken), on real features of two views and on descriptor sets
// with exact ties and single rows.
TEST(FeaturePose, MatchesAsTheBruteForceMatcher) {
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
  const auto brute_force = [&](const OrbFeatures& x, const OrbFeatures& y) { return MatchFeaturesBruteForce(x, y, fo); };
  const auto expect_same = [&](const OrbFeatures& x, const OrbFeatures& y) {
    const std::vector<cv::DMatch> expected = brute_force(x, y), got = MatchFeatures(x, y, fo);
    ASSERT_EQ(got.size(), expected.size());
    for (size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].queryIdx, expected[i].queryIdx);
      EXPECT_EQ(got[i].trainIdx, expected[i].trainIdx) << "query " << got[i].queryIdx;
      EXPECT_EQ(got[i].distance, expected[i].distance);
    }
  };
  EXPECT_GT(brute_force(b, a).size(), 100u);  // Six frames apart: many true matches.
  expect_same(b, a);
  expect_same(a, b);

  // Ties: every keyframe descriptor twice (the nearest and the second nearest equal: no match
  // passes unless the distance is 0, and then the first copy is the match), and a keyframe of one
  // descriptor (no second nearest).
  OrbFeatures doubled;
  cv::vconcat(a.descriptors, a.descriptors, doubled.descriptors);
  expect_same(b, doubled);
  expect_same(a, doubled);
  const std::vector<cv::DMatch> self = MatchFeatures(a, doubled, fo);
  ASSERT_EQ(self.size(), static_cast<size_t>(a.descriptors.rows));
  for (const cv::DMatch& m : self) EXPECT_LT(m.trainIdx, a.descriptors.rows);
  OrbFeatures single;
  single.descriptors = a.descriptors.row(0).clone();
  EXPECT_TRUE(MatchFeatures(b, single, fo).empty());
  EXPECT_TRUE(MatchFeatures(b, OrbFeatures{}, fo).empty());
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/eval/ground_truth_check.h"

#include <gtest/gtest.h>

#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

// The same trajectory with every rotation replaced by its inverse (a JPL/Hamilton mix-up).
Trajectory ConjugateRotations(const Trajectory& t) {
  Trajectory out;
  for (size_t i = 0; i < t.size(); ++i) out.Add(t.stamps_ns[i], SE3d(t.poses[i].So3().Inverse(), t.poses[i].Translation()));
  return out;
}

// The body of a rig whose camera sits 7 cm off and turned 90 degrees, as EuRoC's: poses of the
// body where camera poses are expected.
Trajectory BodyPoses(const Trajectory& t) {
  const SE3d cam_from_body = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
                                  Eigen::Vector3d(0.02, 0.065, -0.01));
  Trajectory out;
  for (size_t i = 0; i < t.size(); ++i) out.Add(t.stamps_ns[i], t.poses[i] * cam_from_body);
  return out;
}

TEST(GroundTruthCheck, RenderedSequenceAgreesOnlyWithItsTrueConvention) {
  synth::SynthOptions synth;
  synth.scene = "shake";
  synth.frames = 40;
  const auto dir = testing::ScratchDir("gt_check") / "sequence";
  synth::WriteSequence(synth::MakeSequence(synth), synth, dir);
  const Dataset d = OpenDataset(dir);

  GtCheckOptions options;
  options.max_pairs = 12;
  const std::vector<PairTracks> tracks = TrackPairs(d, options);
  ASSERT_GE(tracks.size(), 8u);
  const double f = d.camera.fx;
  const EpipolarStats right = EpipolarError(tracks, d, d.ground_truth, options, f);
  const EpipolarStats conjugated = EpipolarError(tracks, d, ConjugateRotations(d.ground_truth), options, f);
  const EpipolarStats body = EpipolarError(tracks, d, BodyPoses(d.ground_truth), options, f);
  ASSERT_GT(right.tracks, 500u);
  EXPECT_GT(right.pairs, 5u);
  EXPECT_LT(right.median_px, 0.3);
  EXPECT_GT(conjugated.median_px, 10 * right.median_px);
  EXPECT_GT(body.median_px, 10 * right.median_px);
  EXPECT_GT(conjugated.median_px, 1.0);
}

TEST(GroundTruthCheck, BadOptionsAreRefused) {
  GtCheckOptions options;
  options.gap = 0;
  EXPECT_THROW(options.Validate(), InputError);
  options = {};
  options.corners = 3;
  EXPECT_THROW(options.Validate(), InputError);
}

}  // namespace
}  // namespace dsm

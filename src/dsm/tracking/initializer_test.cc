// SPDX-License-Identifier: MIT
#include "dsm/tracking/initializer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dsm/geometry/undistorter.h"
#include "dsm/io/dataset.h"
#include "dsm/synth/renderer.h"
#include "dsm/testing/motion_error.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

Image<float> RenderFloat(const synth::SynthSequence& seq, int i) {
  synth::FormationOptions formation;
  formation.noise_sigma = 1.0;
  formation.noise_seed = i;
  return synth::RenderSequenceFrame(seq, i, formation).image;
}

// A scene rendered at 320x240 (the initialiser's tests need no more).
synth::SynthSequence SmallSequence(const std::string& scene, uint32_t seed = 1) {
  synth::SynthOptions options;
  options.scene = scene;
  options.seed = seed;
  options.width = 320;
  options.height = 240;
  return synth::MakeSequence(options);
}

struct MotionError {
  double direction_deg = 0.0;  // Between the directions of translation.
  double rotation_deg = 0.0;
};
MotionError Compare(const SE3d& estimate, const SE3d& truth) {
  return {testing::DirectionErrorDeg(estimate.Translation(), truth.Translation()),
          testing::RotationErrorDeg(estimate.So3(), truth.So3())};
}

// Frame index at which the initializer succeeds on the scene (-1 if never within `max_frames`).
int InitialisesAt(const synth::SynthSequence& seq, int max_frames, InitResult* out,
                  const InitializerOptions& options = {}) {
  Initializer init{options};
  init.SetReference(RenderFloat(seq, 0), seq.camera);
  for (int i = 1; i < max_frames; ++i) {
    *out = init.AddFrame(RenderFloat(seq, i));
    if (out->ok) return i;
  }
  return -1;
}

// Initialises on every synthetic scene and checks the motion against the truth.
void ExpectStartsOnEverySyntheticScene(const InitializerOptions& init_options, double max_direction_deg,
                                       double max_rotation_deg) {
  for (const char* scene : {"loop", "shake", "forward", "rotation", "exposure", "orbit"}) {
    const synth::SynthSequence seq = SmallSequence(scene);
    InitResult r;
    const int at = InitialisesAt(seq, 30, &r, init_options);
    ASSERT_GE(at, 1) << scene << ": " << r.reason;
    const MotionError e = Compare(r.current_from_reference, seq.world_from_cam[at].Inverse() * seq.world_from_cam[0]);
    std::printf("%s: initialised at frame %d, parallax %.2f deg, homography ratio %.2f, direction error %.2f deg, "
                "rotation error %.3f deg\n", scene, at, r.parallax_deg, r.homography_ratio, e.direction_deg, e.rotation_deg);
    EXPECT_LT(e.direction_deg, max_direction_deg) << scene;
    EXPECT_LT(e.rotation_deg, max_rotation_deg) << scene;
    EXPECT_GT(r.points.size(), 60u) << scene;
  }
}

TEST(Initializer, StartsEarlyOnEverySyntheticScene) {
  // RANSAC's best minimal sample: the direction of motion up to about 8 deg off, the rotation 0.5.
  ExpectStartsOnEverySyntheticScene(InitializerOptions{}, 15.0, 1.0);
}

TEST(Initializer, RefusesPureRotation) {
  synth::SynthSequence seq = SmallSequence("loop");
  // Same position, turning 0.4 degrees per frame.
  const SE3d start = seq.world_from_cam[0];
  for (int i = 0; i < 40; ++i) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0, 0, 0, 0, 0.007 * i, 0.002 * i;
    seq.world_from_cam[i] = SE3d(start.So3() * SO3d::Exp(xi.tail<3>()), start.Translation());
  }
  InitResult r;
  EXPECT_EQ(InitialisesAt(seq, 40, &r), -1) << "initialised on a pure rotation";
  EXPECT_FALSE(r.reason.empty());
}

// `pan`: hand-held in front of one wall, turning +-30 deg with a few centimetres of hand motion.
// The homography explains every track, so the essential-matrix start waited for the walk that
// follows (frames 75-182 of five renderings at 20 Hz); the planar start takes the homography's
// solution whose plane stays put (see initializer.h) within the first second, with the tracks'
// depths on that plane.
TEST(Initializer, StartsOnAPlaneWithinTheFirstSecond) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const synth::SynthSequence seq = SmallSequence("pan", seed);
    InitResult r;
    const int at = InitialisesAt(seq, 20, &r);
    ASSERT_GE(at, 1) << "seed " << seed << ": " << r.reason;
    EXPECT_TRUE(r.planar);
    const MotionError e = Compare(r.current_from_reference, seq.world_from_cam[at].Inverse() * seq.world_from_cam[0]);
    // Depths up to the unknown scale: their ratio to the true depth, relative to its median.
    const Image<float> depth = synth::RenderSequenceFrame(seq, 0, {}).depth;
    std::vector<double> ratio;
    for (const InitPoint& p : r.points) {
      const int x = static_cast<int>(std::lround(p.pixel.x())), y = static_cast<int>(std::lround(p.pixel.y()));
      ratio.push_back(depth(x, y) * p.idepth);
    }
    std::sort(ratio.begin(), ratio.end());
    const double median = ratio[ratio.size() / 2];
    std::vector<double> off;
    for (double q : ratio) off.push_back(std::abs(q / median - 1.0));
    std::sort(off.begin(), off.end());
    std::printf("pan seed %u: initialised at frame %d, %zu points, direction error %.2f deg, rotation error %.3f deg, "
                "depth error median %.1f%%, 90%% %.1f%%\n", seed, at, r.points.size(), e.direction_deg, e.rotation_deg,
                100 * off[off.size() / 2], 100 * off[off.size() * 9 / 10]);
    EXPECT_LT(e.direction_deg, 15.0);
    EXPECT_LT(e.rotation_deg, 1.0);
    EXPECT_GT(r.points.size(), 60u);
    EXPECT_LT(off[off.size() * 9 / 10], 0.1);
  }
}

TEST(Initializer, RefusesPureRotationInFrontOfAPlane) {
  synth::SynthSequence seq = SmallSequence("pan");
  // The panning without the hand's motion.
  for (int i = 1; i < 40; ++i)
    seq.world_from_cam[i] = SE3d(seq.world_from_cam[i].So3(), seq.world_from_cam[0].Translation());
  InitResult r;
  EXPECT_EQ(InitialisesAt(seq, 40, &r), -1) << "initialised on a pure rotation";
}

TEST(Initializer, StartsWithinTwentyFramesOnTheSharedEuroc) {
  // Only the start is asserted here: a two-view estimate over a few centimetres of baseline is a
  // starting point, and the photometric bundle adjustment that follows makes the map accurate
  // (tests/shared_run_test checks the result against the ground truth).
  const Dataset d = OpenDataset(testing::SharedDataDir() / "euroc_mh01_shake");
  const Undistorter und(d.camera, {d.undistort_mode, 16});
  const auto load = [&](size_t i) {
    return und.Apply(ToFloat(d.LoadImage(i)));
  };
  Initializer init{InitializerOptions{}};
  init.SetReference(load(0), und.output());
  int at = -1;
  InitResult r;
  for (int i = 1; i < 20 && at < 0; ++i) {
    r = init.AddFrame(load(i));
    if (r.ok) at = i;
  }
  ASSERT_GE(at, 1) << r.reason;
  EXPECT_GE(r.parallax_deg, InitializerOptions{}.min_parallax_deg);
  EXPECT_GT(r.points.size(), 100u);
  for (const InitPoint& p : r.points) EXPECT_TRUE(p.idepth > 0.f && std::isfinite(p.idepth));
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/tracking/initializer.h"

#include <gtest/gtest.h>

#include "dsm/geometry/undistorter.h"
#include "dsm/io/dataset.h"
#include "dsm/synth/renderer.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

Image<float> RenderFloat(const synth::SynthSequence& seq, int i) {
  synth::FormationOptions formation;
  formation.noise_sigma = 1.0;
  formation.noise_seed = i;
  return synth::RenderSequenceFrame(seq, i, formation).image;
}

// Frame index at which the initializer succeeds on the scene (-1 if never within `max_frames`).
int InitialisesAt(const synth::SynthSequence& seq, int max_frames, InitResult* out) {
  Initializer init{InitializerOptions{}};
  init.SetReference(RenderFloat(seq, 0), seq.camera);
  for (int i = 1; i < max_frames; ++i) {
    *out = init.AddFrame(RenderFloat(seq, i));
    if (out->ok) return i;
  }
  return -1;
}

TEST(Initializer, StartsEarlyOnEverySyntheticScene) {
  for (const char* scene : {"loop", "shake", "forward", "rotation", "exposure", "orbit"}) {
    synth::SynthOptions options;
    options.scene = scene;
    options.width = 320;
    options.height = 240;
    const synth::SynthSequence seq = synth::MakeSequence(options);
    InitResult r;
    const int at = InitialisesAt(seq, 30, &r);
    ASSERT_GE(at, 1) << scene << ": " << r.reason;
    std::printf("%s: initialised at frame %d, parallax %.2f deg, homography ratio %.2f\n", scene, at, r.parallax_deg, r.homography_ratio);
    // The estimated direction of motion matches the truth.
    const SE3d truth = seq.world_from_cam[at].Inverse() * seq.world_from_cam[0];
    const double cos_angle = r.current_from_reference.Translation().normalized().dot(truth.Translation().normalized());
    EXPECT_GT(cos_angle, 0.95) << scene;
    EXPECT_LT((r.current_from_reference.So3() * truth.So3().Inverse()).Log().norm() * 180 / M_PI, 1.0) << scene;
    EXPECT_GT(r.points.size(), 60u) << scene;
  }
}

TEST(Initializer, RefusesPureRotation) {
  synth::SynthOptions options;
  options.scene = "loop";
  options.width = 320;
  options.height = 240;
  synth::SynthSequence seq = synth::MakeSequence(options);
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

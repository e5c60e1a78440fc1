// SPDX-License-Identifier: MIT
#include "dsm/tracking/rolling_shutter.h"

#include <cmath>

#include <gtest/gtest.h>

#include "dsm/lie/so3.h"
#include "dsm/synth/renderer.h"

namespace dsm {
namespace {

// Mean absolute difference over the pixels at least `border` from the edges.
double MeanDifference(const Image<float>& a, const Image<float>& b, int border) {
  double sum = 0.0;
  int n = 0;
  for (int v = border; v < a.height() - border; ++v)
    for (int u = border; u < a.width() - border; ++u, ++n) sum += std::abs(a(u, v) - b(u, v));
  return sum / n;
}

TEST(RectifyRotation, UndoesARollingShutterWhileTheCameraTurns) {
  synth::SynthOptions options;
  options.scene = "loop";
  options.frames = 2;
  const synth::SynthSequence seq = synth::MakeSequence(options);
  const SE3d world_from_t0 = synth::LookAt({0.3, -0.4, 1.5}, {2.0, 1.0, 1.3});
  // Turning at 90 deg/s about an axis mostly along the image's vertical (a pan), with some roll;
  // 30 us per row: 14.4 ms of readout over 480 rows.
  const Eigen::Vector3d w = (M_PI / 2) * Eigen::Vector3d(0.2, 0.9, 0.4).normalized();
  const double delta = 30e-6;
  std::vector<SE3d> rows(seq.camera.height);
  for (int v = 0; v < seq.camera.height; ++v)
    rows[v] = world_from_t0 * SE3d(SO3d::Exp(w * (v * delta)).Inverse(), Eigen::Vector3d::Zero());
  Image<float> global, rolling;
  synth::RenderFrame(seq.scene, seq.camera, world_from_t0, &global, nullptr);
  synth::RenderRollingShutterFrame(seq.scene, seq.camera, rows, &rolling, nullptr);
  const Image<float> rectified = RectifyRotation(rolling, seq.camera, {delta, w});
  // The lowest rows moved by ~9 px: far off before, a resampling's blur after. The border strip
  // the turn brought in from outside the image is left out.
  const double before = MeanDifference(rolling, global, 12), after = MeanDifference(rectified, global, 12);
  EXPECT_GT(before, 0.05);
  EXPECT_LT(after, 0.15 * before);
  // Nothing turns: the image comes back as it was.
  const Image<float> still = RectifyRotation(rolling, seq.camera, {delta, Eigen::Vector3d::Zero()});
  EXPECT_LT(MeanDifference(still, rolling, 0), 1e-6);
}

}  // namespace
}  // namespace dsm

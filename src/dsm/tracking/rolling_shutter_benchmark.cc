// SPDX-License-Identifier: MIT
// Rolling-shutter rectification of a 640x480 frame (a rendered frame of the hand-held scene)
// turning at 90 deg/s with 30 us per row, against building the frame's pyramid, the work it
// adds to before tracking.
#include <benchmark/benchmark.h>

#include "dsm/image/pyramid.h"
#include "dsm/synth/renderer.h"
#include "dsm/tracking/rolling_shutter.h"

namespace dsm {
namespace {

struct Fixture {
  PinholeCamera camera;
  Image<float> image;
};

const Fixture& GetFixture() {
  static const Fixture f = [] {
    synth::SynthOptions options;
    options.scene = "handheld";
    options.frames = 40;
    const synth::SynthSequence seq = synth::MakeSequence(options);
    return Fixture{seq.camera, synth::RenderSequenceFrame(seq, 30, {}).image};
  }();
  return f;
}

void BM_RectifyRotation(benchmark::State& state) {
  const Fixture& f = GetFixture();
  const Eigen::Vector3d w = (M_PI / 2) * Eigen::Vector3d(0.2, 0.9, 0.4).normalized();
  for (auto _ : state) benchmark::DoNotOptimize(RectifyRotation(f.image, f.camera, {30e-6, w}));
}
BENCHMARK(BM_RectifyRotation)->Unit(benchmark::kMicrosecond);

void BM_FramePyramid(benchmark::State& state) {
  const Fixture& f = GetFixture();
  for (auto _ : state) benchmark::DoNotOptimize(ImagePyramid(f.image, 5, /*gradients=*/false));
}
BENCHMARK(BM_FramePyramid)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

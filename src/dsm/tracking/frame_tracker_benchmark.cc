// SPDX-License-Identifier: MIT
// Frame tracking time on rendered 640x480 frames of the loop: about 1500 reference points (the
// system's target) with their true inverse depths, a frame 3 steps later tracked from the
// identity (all pyramid levels), and the cost of one evaluation of the normal equations at level 0.
#include <benchmark/benchmark.h>

#include "dsm/synth/renderer.h"
#include "dsm/tracking/frame_tracker.h"

namespace dsm {
namespace {

struct Fixture {
  synth::SynthSequence seq;
  ImagePyramid reference, frame;
  std::vector<ReferencePoint> points;
};

const Fixture& GetFixture() {
  static const Fixture f = [] {
    synth::SynthOptions options;
    options.scene = "loop";
    Fixture fx;
    fx.seq = synth::MakeSequence(options);
    synth::FormationOptions formation;
    const synth::RenderedFrame a = synth::RenderSequenceFrame(fx.seq, 40, formation);
    const synth::RenderedFrame b = synth::RenderSequenceFrame(fx.seq, 43, formation);
    fx.reference = ImagePyramid(a.image, 5);
    fx.frame = ImagePyramid(b.image, 5, /*gradients=*/false);  // As System::Process makes a frame's.
    // Every 12th pixel with some gradient: about the system's 1500 points.
    for (int y = 8; y < a.image.height() - 8; y += 12)
      for (int x = 8; x < a.image.width() - 8; x += 12) {
        const PixelGrad g = fx.reference.At(0, x, y);
        if (g[1] * g[1] + g[2] * g[2] > 25.f && a.depth(x, y) > 0.f)
          fx.points.push_back({Eigen::Vector2f(x, y), 1.f / a.depth(x, y)});
      }
    return fx;
  }();
  return f;
}

void BM_Track(benchmark::State& state) {
  const Fixture& f = GetFixture();
  FrameTracker tracker{TrackerOptions{}};
  tracker.SetReference(&f.reference, f.seq.camera, f.points);
  TrackResult r;
  for (auto _ : state) {
    r = tracker.Track(f.frame, SE3d(), 0.0, 0.0);
    benchmark::DoNotOptimize(r.rmse);
  }
  state.counters["points"] = static_cast<double>(f.points.size());
  state.counters["iterations"] = r.iterations;
}
BENCHMARK(BM_Track)->Unit(benchmark::kMillisecond);

void BM_TrackOneIterationLevel0(benchmark::State& state) {
  const Fixture& f = GetFixture();
  TrackerOptions options;
  options.levels = 1;
  options.iterations = {1};
  FrameTracker tracker{options};
  tracker.SetReference(&f.reference, f.seq.camera, f.points);
  for (auto _ : state) benchmark::DoNotOptimize(tracker.Track(f.frame, SE3d(), 0.0, 0.0).rmse);
  state.counters["pixels"] = static_cast<double>(f.points.size() * kPatternSize);
}
BENCHMARK(BM_TrackOneIterationLevel0)->Unit(benchmark::kMicrosecond);

// The pyramid every frame needs (5 levels with gradients), built from a 752x480 image (EuRoC's size).
void BM_BuildPyramid(benchmark::State& state) {
  const Fixture& f = GetFixture();
  Image<float> image(752, 480);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) image(x, y) = f.reference.Value(0, x % f.reference.width(0), y % f.reference.height(0));
  for (auto _ : state) {
    const ImagePyramid pyramid(image, 5);
    benchmark::DoNotOptimize(pyramid.At(4, 0, 0));
  }
}
BENCHMARK(BM_BuildPyramid)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

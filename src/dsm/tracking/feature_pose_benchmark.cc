// SPDX-License-Identifier: MIT
// Ranking relocalisation candidates: the ratio-test match count of a frame's ORB features against
// a keyframe's (rendered 640x480 loop frames six steps apart, up to 1000 features each), by
// MatchFeatures and by OpenCV's brute-force matcher it replaces, and the detection itself.
#include <benchmark/benchmark.h>

#include "dsm/synth/renderer.h"
#include "dsm/tracking/feature_pose.h"

namespace dsm {
namespace {

struct Fixture {
  ImagePyramid frame;
  OrbFeatures a, b;
};

const Fixture& GetFixture() {
  static const Fixture f = [] {
    synth::SynthOptions options;
    options.scene = "loop";
    const synth::SynthSequence seq = synth::MakeSequence(options);
    const synth::FormationOptions formation;
    Fixture fx;
    fx.frame = ImagePyramid(synth::RenderSequenceFrame(seq, 100, formation).image, 5);
    fx.a = DetectOrbFeatures(fx.frame, {});
    fx.b = DetectOrbFeatures(ImagePyramid(synth::RenderSequenceFrame(seq, 106, formation).image, 5), {});
    return fx;
  }();
  return f;
}

void BM_MatchFeatures(benchmark::State& state) {
  const Fixture& f = GetFixture();
  for (auto _ : state) benchmark::DoNotOptimize(MatchFeatures(f.b, f.a, {}));
}
BENCHMARK(BM_MatchFeatures)->Unit(benchmark::kMillisecond);

void BM_MatchFeaturesBruteForce(benchmark::State& state) {
  const Fixture& f = GetFixture();
  for (auto _ : state) benchmark::DoNotOptimize(MatchFeaturesBruteForce(f.b, f.a, {}));
}
BENCHMARK(BM_MatchFeaturesBruteForce)->Unit(benchmark::kMillisecond);

void BM_DetectOrbFeatures(benchmark::State& state) {
  const Fixture& f = GetFixture();
  for (auto _ : state) benchmark::DoNotOptimize(DetectOrbFeatures(f.frame, {}));
}
BENCHMARK(BM_DetectOrbFeatures)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

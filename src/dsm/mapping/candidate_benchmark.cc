// SPDX-License-Identifier: MIT
// Candidate selection on a keyframe (block thresholds, noise floor, the adaptive grid search) on a
// rendered loop frame tiled to 752x480 (EuRoC's size).
#include <benchmark/benchmark.h>

#include "dsm/mapping/candidate_selector.h"
#include "dsm/synth/renderer.h"

namespace dsm {
namespace {

const ImagePyramid& Keyframe() {
  static const ImagePyramid pyramid = [] {
    synth::SynthOptions options;
    options.scene = "loop";
    const synth::SynthSequence seq = synth::MakeSequence(options);
    const synth::RenderedFrame a = synth::RenderSequenceFrame(seq, 40, synth::FormationOptions{});
    Image<float> image(752, 480);
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) image(x, y) = a.image(x % a.image.width(), y % a.image.height());
    return ImagePyramid(image, 5);
  }();
  return pyramid;
}

void BM_SelectCandidates(benchmark::State& state) {
  const ImagePyramid& pyramid = Keyframe();
  size_t selected = 0;
  for (auto _ : state) {
    selected = SelectCandidates(pyramid, CandidateSelectorOptions{}).size();
    benchmark::DoNotOptimize(selected);
  }
  state.counters["selected"] = static_cast<double>(selected);
}
BENCHMARK(BM_SelectCandidates)->Unit(benchmark::kMillisecond);

void BM_BlockThresholds(benchmark::State& state) {
  const ImagePyramid& pyramid = Keyframe();
  for (auto _ : state) benchmark::DoNotOptimize(ComputeBlockThresholds(pyramid, CandidateSelectorOptions{}).select(0, 0));
}
BENCHMARK(BM_BlockThresholds)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

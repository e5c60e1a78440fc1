// SPDX-License-Identifier: MIT
// Candidate selection on a keyframe (block thresholds, noise floor, the adaptive grid search) on a
// rendered loop frame tiled to 752x480 (EuRoC's size); the epipolar search of a keyframe's
// candidates in a frame four frames later (the candidates' refinement with every tracked frame).
#include <benchmark/benchmark.h>

#include "dsm/mapping/candidate.h"
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

// Arguments: none. Each iteration traces all candidates once from their initial (unbounded) range.
void BM_TraceCandidates(benchmark::State& state) {
  synth::SynthOptions options;
  options.scene = "loop";
  const synth::SynthSequence seq = synth::MakeSequence(options);
  const synth::RenderedFrame host = synth::RenderSequenceFrame(seq, 40, synth::FormationOptions{});
  const synth::RenderedFrame frame = synth::RenderSequenceFrame(seq, 44, synth::FormationOptions{});
  const ImagePyramid host_pyramid(host.image, 4);
  const ImagePyramid frame_pyramid(frame.image, 4, false);  // A tracked frame's: intensities only.
  const SE3d frame_from_host = seq.world_from_cam[44].Inverse() * seq.world_from_cam[40];
  std::vector<Candidate> candidates;
  for (const auto& s : SelectCandidates(host_pyramid, CandidateSelectorOptions{})) {
    Candidate c;
    if (MakeCandidate(host_pyramid, s.pixel, &c)) candidates.push_back(c);
  }
  int good = 0;
  for (auto _ : state) {
    good = 0;
    for (const Candidate& c0 : candidates) {
      Candidate c = c0;
      good += TraceCandidate(&c, frame_pyramid, seq.camera, frame_from_host, {}, EpipolarOptions{}) == TraceStatus::kGood;
    }
    benchmark::DoNotOptimize(good);
  }
  state.counters["candidates"] = static_cast<double>(candidates.size());
  state.counters["good"] = good;
}
BENCHMARK(BM_TraceCandidates)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

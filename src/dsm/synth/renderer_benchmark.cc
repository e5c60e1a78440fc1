// SPDX-License-Identifier: MIT
// Ray casting time per 640x480 frame on one core (the synthetic world's budget is 30 ms).
#include <benchmark/benchmark.h>

#include "dsm/synth/renderer.h"

namespace dsm::synth {
namespace {

void BM_RenderFrameOneCore(benchmark::State& state) {
  SynthOptions options;
  options.scene = SceneNames()[state.range(0)];
  const SynthSequence seq = MakeSequence(options);
  SampleNoiseTile(0.f, 0.f, 1.f);  // Builds the shared noise tile before timing.
  Image<float> albedo;
  size_t i = 0;
  for (auto _ : state) {
    RenderFrame(seq.scene, seq.camera, seq.world_from_cam[i], &albedo, nullptr, /*parallel=*/false);
    benchmark::DoNotOptimize(albedo.data());
    i = (i + 37) % seq.size();
  }
  state.SetLabel(options.scene);
}
BENCHMARK(BM_RenderFrameOneCore)->DenseRange(0, static_cast<int>(SceneNames().size()) - 1)->Unit(benchmark::kMillisecond);

void BM_EvaluateTexture(benchmark::State& state) {
  const Texture texture{7, 0.5f, 0.3f, 1.0f, 0.5f, 0.3f};
  float u = 0.f, acc = 0.f;
  SampleNoiseTile(0.f, 0.f, 1.f);
  for (auto _ : state) {
    acc += EvaluateTexture(texture, u, 0.37f * u, 0.004f);
    u += 0.0013f;
  }
  benchmark::DoNotOptimize(acc);
}
BENCHMARK(BM_EvaluateTexture);

}  // namespace
}  // namespace dsm::synth

BENCHMARK_MAIN();

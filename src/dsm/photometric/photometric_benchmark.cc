// SPDX-License-Identifier: MIT
// The robust fit at the sizes the tracker (600 residuals, once per level) and the bundle
// adjustment (3000 per keyframe) use, on t-distributed residuals with 10% gross outliers.
#include <random>

#include <benchmark/benchmark.h>

#include "dsm/photometric/robust.h"

namespace dsm {
namespace {

std::vector<float> Residuals(int n) {
  std::mt19937 rng(7);
  std::student_t_distribution<float> t(4.0f);
  std::uniform_real_distribution<float> gross(-60.f, 60.f), u(0.f, 1.f);
  std::vector<float> r(n);
  for (float& v : r) v = u(rng) < 0.1f ? gross(rng) : 6.f * t(rng);
  return r;
}

void BM_FitErrorModel(benchmark::State& state) {
  const std::vector<float> r = Residuals(static_cast<int>(state.range(0)));
  RobustOptions options;
  options.max_fit_samples = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(FitErrorModel(r, options).sigma);
}
BENCHMARK(BM_FitErrorModel)->Arg(600)->Arg(3000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

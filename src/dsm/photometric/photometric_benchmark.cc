// SPDX-License-Identifier: MIT
// The robust fit at the sizes the tracker (600 residuals, once per level) and the bundle
// adjustment (3000 per keyframe) use, on t-distributed residuals with 10% gross outliers; and one
// observation's residuals on 752x480 level-0 keyframes, in one target (in cache) and spread over
// as many targets as a bundle adjustment holds (the images far larger than the caches).
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include "dsm/photometric/residual.h"
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

// Arguments: targets, derivatives (0 none, 2 all), spread (patch centres over the whole image, or
// 1: in a 48x48 corner that stays in the caches), interpolation (0 bilinear, 1 B-spline). Random
// textured images, random patches, a small motion between host and target.
void BM_EvaluateObservation(benchmark::State& state) {
  const int num_targets = static_cast<int>(state.range(0));
  const auto derivatives = static_cast<Derivatives>(state.range(1));
  constexpr int kWidth = 752, kHeight = 480;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> grey(0.f, 255.f);
  std::vector<ImagePyramid> targets;
  for (int t = 0; t < num_targets; ++t) {
    Image<float> image(kWidth, kHeight);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) image(x, y) = 0.5f * grey(rng) + 60.f * std::sin(0.05f * x + 0.07f * y);
    targets.emplace_back(std::move(image), 1);
  }
  const PinholeCamera camera{kWidth, kHeight, 450.0, 450.0, 375.5, 239.5};
  const bool hot = state.range(2) != 0;
  std::uniform_real_distribution<float> ux(20.f, hot ? 68.f : kWidth - 20.f), uy(20.f, hot ? 68.f : kHeight - 20.f);
  constexpr int kObservations = 4096;
  std::vector<HostPatch> patches(kObservations);
  std::vector<int> target_of(kObservations);
  for (int i = 0; i < kObservations; ++i) {
    patches[i].center = Eigen::Vector2f(ux(rng), uy(rng));
    patches[i].interpolation = state.range(3) != 0 ? Interpolation::kBSpline : Interpolation::kBilinear;
    for (int k = 0; k < kPatternSize; ++k) {
      patches[i].value[k] = grey(rng);
      patches[i].weight_g[k] = 0.5f;
    }
    target_of[i] = i % num_targets;
  }
  ObservationInput in;
  in.camera = &camera;
  in.R = Eigen::AngleAxisf(0.01f, Eigen::Vector3f(0.3f, 1.f, 0.1f).normalized()).toRotationMatrix();
  in.t = Eigen::Vector3f(0.02f, -0.01f, 0.01f);
  in.idepth = 0.5f;
  ObservationResiduals res;
  int64_t evaluated = 0;
  for (auto _ : state) {
    for (int i = 0; i < kObservations; ++i) {
      in.target = &targets[target_of[i]];
      benchmark::DoNotOptimize(EvaluateObservation(patches[i], in, derivatives, &res));
      benchmark::DoNotOptimize(res.r[0]);
    }
    evaluated += kObservations;
  }
  // Seconds per (observations / 1e9): nanoseconds per observation.
  state.counters["ns_per_observation"] = benchmark::Counter(
      1e-9 * static_cast<double>(evaluated), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_EvaluateObservation)
    ->Args({1, 0, 1, 0})
    ->Args({1, 2, 1, 0})
    ->Args({1, 2, 1, 1})
    ->Args({1, 0, 0, 0})
    ->Args({40, 0, 0, 0})
    ->Args({40, 2, 0, 0})
    ->Args({40, 2, 0, 1});

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

// SPDX-License-Identifier: MIT
// Photometric bundle adjustment time on rendered 640x480 keyframes: two host keyframes whose points
// are observed in all the others, poses and depths perturbed, keyframe 0 fixed; the problem a
// window of that many keyframes solves. Arguments: keyframes, pyramid levels.
#include <benchmark/benchmark.h>

#include "dsm/optimization/pba.h"
#include "dsm/optimization/pba_world.h"

namespace dsm {
namespace {

void BM_Pba(benchmark::State& state) {
  const int keyframes = static_cast<int>(state.range(0));
  testing::World w;
  std::vector<int> frames, active;
  for (int k = 0; k < keyframes; ++k) {
    frames.push_back(6 * k);
    active.push_back(k);
  }
  testing::BuildWorld(frames, &w, 4, 0.0, 640, 480);
  testing::Perturb(&w);
  // The perturbed state, restored before every solve.
  std::vector<SE3d> poses;
  std::vector<AffineBrightness> affine;
  std::vector<float> idepth;
  for (int k = 0; k < keyframes; ++k) {
    poses.push_back(w.map.keyframe(k).cam_from_world);
    affine.push_back(w.map.keyframe(k).affine);
  }
  for (int i = 0; i < w.map.NumPoints(); ++i) idepth.push_back(w.map.point(i).idepth);
  PbaOptions options;
  options.levels = static_cast<int>(state.range(1));
  PbaSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    for (int k = 0; k < keyframes; ++k) {
      w.map.keyframe(k).cam_from_world = poses[k];
      w.map.keyframe(k).affine = affine[k];
      w.map.keyframe(k).error_model = DefaultErrorModel(options.robust);
    }
    for (int i = 0; i < w.map.NumPoints(); ++i) {
      w.map.point(i).idepth = idepth[i];
      for (Observation& o : w.map.point(i).observations) o.outlier = false;
    }
    state.ResumeTiming();
    summary = RunPba(&w.map, w.seq.camera, active, options);
    benchmark::DoNotOptimize(summary.final_energy);
  }
  state.counters["observations"] = summary.observations;
  state.counters["iterations"] = summary.iterations;
  state.counters["time_per_obs_iteration"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * summary.observations * summary.iterations,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}
BENCHMARK(BM_Pba)->Args({4, 2})->Args({8, 2})->Args({8, 1})->Args({8, 3})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

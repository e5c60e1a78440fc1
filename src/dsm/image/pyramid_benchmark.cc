// SPDX-License-Identifier: MIT
// Building a keyframe's pyramid with gradients from its 16-bit level 0 (Map::LoadPyramids rebuilds
// one for every keyframe a bundle adjustment needs after it was released; every new keyframe gets
// one), at 640x480 and 752x480, five levels.
#include <random>

#include <benchmark/benchmark.h>

#include "dsm/image/pyramid.h"

namespace dsm {
namespace {

void BM_PyramidFromFixed(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = 480;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> grey(0, 255 * 64);
  Image<uint16_t> level0(w, h);
  for (size_t i = 0; i < level0.size(); ++i) level0.data()[i] = static_cast<uint16_t>(grey(rng));
  for (auto _ : state) benchmark::DoNotOptimize(ImagePyramid::FromFixed(level0, 5).levels());
}
BENCHMARK(BM_PyramidFromFixed)->Arg(640)->Arg(752)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

// SPDX-License-Identifier: MIT
// Undistortion of one EuRoC-sized frame (752 x 480, radial-tangential): the 8-bit input as frames
// are read (vectorised remap) and its float copy (the scalar remap), which give the same floats.
#include <benchmark/benchmark.h>

#include "dsm/geometry/undistorter.h"

namespace dsm {
namespace {

const CameraCalibration kEuroc{CameraModel::kRadTan, 752, 480, 458.654, 457.296, 367.215, 248.375,
                               {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}};

Image<uint8_t> Frame() {
  Image<uint8_t> raw(kEuroc.width, kEuroc.height);
  for (int v = 0; v < raw.height(); ++v)
    for (int u = 0; u < raw.width(); ++u) raw(u, v) = static_cast<uint8_t>((u * 7 + v * 13 + u * v * 31) % 256);
  return raw;
}

void BM_Undistort8Bit(benchmark::State& state) {
  const Undistorter und(kEuroc, {});
  const Image<uint8_t> raw = Frame();
  for (auto _ : state) benchmark::DoNotOptimize(und.Apply(raw).data());
}
BENCHMARK(BM_Undistort8Bit)->Unit(benchmark::kMicrosecond);

void BM_UndistortFloat(benchmark::State& state) {
  const Undistorter und(kEuroc, {});
  const Image<float> raw = ToFloat(Frame());
  for (auto _ : state) benchmark::DoNotOptimize(und.Apply(raw).data());
}
BENCHMARK(BM_UndistortFloat)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dsm

BENCHMARK_MAIN();

// SPDX-License-Identifier: MIT
// The generic folder layout (what `dsm synth` writes): camera.yaml, times.txt, groundtruth.tum.
#include "fuzz/fuzz_input.h"

namespace {

const dsm::fuzz::Layout& FolderLayout() {
  static const dsm::fuzz::Layout layout = [] {
    const auto root = dsm::fuzz::Scratch() / "folder";
    for (int i = 0; i < 3; ++i) {
      dsm::fuzz::WritePng(root / "images" / ("00000" + std::to_string(i) + ".png"), 96, 64);
      dsm::fuzz::WritePng(root / "rate/images" / ("00000" + std::to_string(i) + ".png"), 96, 64);
    }
    return dsm::fuzz::Layout(
        root,
        {{"camera.yaml", "model: fov\nwidth: 96\nheight: 64\nintrinsics: [50.2, 50.1, 47.5, 31.5]\n"
                         "distortion: [0.9]\nrate_hz: 30\n", ""},
         {"times.txt", "# timestamp_ns exposure_ms\n0 10.0\n33333333 10.5\n66666667 11.0\n", ""},
         {"groundtruth.tum", "# timestamp tx ty tz qx qy qz qw\n0.000000000 0 0 0 0 0 0 1\n"
                             "0.033333333 0.01 0.002 -0.001 0.001 0.002 0.0005 0.9999972\n", ""},
         // Without a times file the stamps come from rate_hz.
         {"rate/camera.yaml", "model: pinhole\nwidth: 96\nheight: 64\nintrinsics: [50.2, 50.1, 47.5, 31.5]\n"
                              "rate_hz: 20\n", "rate"}});
  }();
  return layout;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::fuzz::FuzzDataset(FolderLayout(), data, size);
  return 0;
}

// SPDX-License-Identifier: MIT
// TUM monoVO (camera.txt, times.txt, pcalib.txt) and TUM RGB-D (rgb.txt, groundtruth.txt,
// camera.yaml) layouts.
#include <string>

#include "fuzz/fuzz_input.h"

namespace {

std::string Pcalib() {
  std::string text;
  for (int i = 0; i < 256; ++i) text += std::to_string(i) + (i % 16 == 15 ? "\n" : " ");
  return text;
}

const dsm::fuzz::Layout& TumLayout() {
  static const dsm::fuzz::Layout layout = [] {
    const auto root = dsm::fuzz::Scratch() / "tum";
    for (int i = 0; i < 3; ++i) {
      dsm::fuzz::WritePng(root / "mono/images" / ("0000" + std::to_string(i) + ".png"), 96, 64);
      dsm::fuzz::WritePng(root / "rgbd/rgb" / ("1305031102.2" + std::to_string(i) + ".png"), 96, 64);
    }
    return dsm::fuzz::Layout(
        root,
        {{"mono/camera.txt", "RadTan 0.61 0.92 0.49 0.5 -0.28 0.07 0.0002 0.00002\n96 64\ncrop\n96 64\n", "mono"},
         {"mono/times.txt", "00000 1403636579.763555584 20.0\n00001 1403636579.813555584 20.5\n"
                            "00002 1403636579.863555584 21.0\n", "mono"},
         {"mono/pcalib.txt", Pcalib(), "mono"},
         {"rgbd/rgb.txt", "# color images\n1305031102.20 rgb/1305031102.20.png\n1305031102.21 rgb/1305031102.21.png\n"
                          "1305031102.22 rgb/1305031102.22.png\n", "rgbd"},
         {"rgbd/groundtruth.txt", "# timestamp tx ty tz qx qy qz qw\n"
                                  "1305031102.1758 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
                                  "1305031102.2158 1.3303 0.6256 1.6464 0.6579 0.6161 -0.2932 -0.3189\n", "rgbd"},
         {"rgbd/camera.yaml", "model: radtan\nwidth: 96\nheight: 64\nintrinsics: [77.6, 77.5, 47.8, 38.3]\n"
                              "distortion: [0.2624, -0.9531, -0.0054, 0.0026, 1.1633]\n", "rgbd"}});
  }();
  return layout;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::fuzz::FuzzDataset(TumLayout(), data, size);
  return 0;
}

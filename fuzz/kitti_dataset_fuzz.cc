// SPDX-License-Identifier: MIT
// KITTI odometry layout: calib.txt, times.txt and poses.txt beside image_0/.
#include "fuzz/fuzz_input.h"

namespace {

const dsm::fuzz::Layout& KittiLayout() {
  static const dsm::fuzz::Layout layout = [] {
    const auto root = dsm::fuzz::Scratch() / "kitti";
    for (int i = 0; i < 3; ++i) dsm::fuzz::WritePng(root / "image_0" / ("00000" + std::to_string(i) + ".png"), 96, 64);
    return dsm::fuzz::Layout(
        root,
        {{"calib.txt", "P0: 71.8856 0.0 60.7192 0.0 0.0 71.8856 18.5215 0.0 0.0 0.0 1.0 0.0\n"
                       "P1: 71.8856 0.0 60.7192 -38.6145 0.0 71.8856 18.5215 0.0 0.0 0.0 1.0 0.0\n", ""},
         {"times.txt", "0.000000e+00\n1.036400e-01\n2.073480e-01\n", ""},
         {"poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n"
                       "9.999978e-01 5.272628e-04 -2.066935e-03 -4.690294e-02 -5.296506e-04 9.999992e-01 "
                       "-1.154865e-03 -2.839928e-02 2.066324e-03 1.155958e-03 9.999971e-01 8.586941e-01\n"
                       "9.999910e-01 1.048972e-03 -4.131348e-03 -9.374345e-02 -1.058514e-03 9.999968e-01 "
                       "-2.308104e-03 -5.676064e-02 4.128913e-03 2.312456e-03 9.999887e-01 1.716275e+00\n", ""}});
  }();
  return layout;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::fuzz::FuzzDataset(KittiLayout(), data, size);
  return 0;
}

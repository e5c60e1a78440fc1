// SPDX-License-Identifier: MIT
// EuRoC layout: cam0/sensor.yaml, the image list cam0/data.csv and the ground-truth CSV.
#include "fuzz/fuzz_input.h"

namespace {

const dsm::fuzz::Layout& EurocLayout() {
  static const dsm::fuzz::Layout layout = [] {
    const auto root = dsm::fuzz::Scratch() / "euroc";
    for (int i = 0; i < 3; ++i)
      dsm::fuzz::WritePng(root / "mav0/cam0/data" / (std::to_string(1403636579763555584 + i * 50000000LL) + ".png"),
                          96, 64);
    return dsm::fuzz::Layout(
        root,
        {{"mav0/cam0/sensor.yaml",
          "sensor_type: camera\n"
          "T_BS:\n  cols: 4\n  rows: 4\n"
          "  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,\n"
          "         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,\n"
          "        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,\n"
          "         0.0, 0.0, 0.0, 1.0]\n"
          "rate_hz: 20\nresolution: [96, 64]\ncamera_model: pinhole\n"
          "intrinsics: [58.7, 58.5, 47.0, 31.8]\n"
          "distortion_model: radial-tangential\n"
          "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n", ""},
         {"mav0/cam0/data.csv",
          "#timestamp [ns],filename\n"
          "1403636579763555584,1403636579763555584.png\n"
          "1403636579813555584,1403636579813555584.png\n"
          "1403636579863555584,1403636579863555584.png\n", ""},
         {"mav0/state_groundtruth_estimate0/data.csv",
          "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []\n"
          "1403636579758555392,4.688319,-1.786938,0.783338,0.534108,-0.153029,-0.827383,-0.082152\n"
          "1403636579763555584,4.688177,-1.786770,0.787350,0.534640,-0.152990,-0.826976,-0.082709\n"
          "1403636579813555584,4.687385,-1.785981,0.787796,0.535006,-0.152716,-0.826770,-0.082889\n", ""}});
  }();
  return layout;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dsm::fuzz::FuzzDataset(EurocLayout(), data, size);
  return 0;
}

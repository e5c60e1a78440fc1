// SPDX-License-Identifier: MIT
// dsm calibrate: a camera's geometric calibration from views of a checkerboard or a ChArUco board
// (calibration/calibrate.h), written as the camera.yaml dsm run reads.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "dsm/run/map_run.h"
#include "dsm/calibration/calibrate.h"
#include "dsm/io/calibration_io.h"
#include "dsm/util/check.h"

namespace dsm::cli {

namespace {

struct CalibrateArgs {
  std::string input, board, model = "radtan", out = "camera.yaml", json;
  int max_views = 40;
};

void PrintReport(const CalibrationResult& r) {
  std::printf("%-7s %-8s %-8s\n", "frame", "corners", "rms px");
  for (const CalibrationView& v : r.views) {
    if (v.used)
      std::printf("%-7d %-8d %-8.3f\n", v.frame, v.corners, v.rms_px);
    else
      std::printf("%-7d %-8d %-8s not used: %s\n", v.frame, v.corners, "-", v.why_not.c_str());
  }
  const CameraCalibration& c = r.camera;
  std::printf("board found in %zu of %d frames, %d views used, reprojection RMS %.3f px\n", r.views.size(), r.frames,
              r.views_used, r.rms_px);
  std::printf("%s: fx %.3f fy %.3f cx %.3f cy %.3f", CameraModelName(c.model).c_str(), c.fx, c.fy, c.cx, c.cy);
  if (!c.distortion.empty()) {
    std::printf(" distortion");
    for (double d : c.distortion) std::printf(" %.6g", d);
  }
  std::printf("\n");
  if (!r.uncovered.empty()) {
    std::printf("no corner covered these parts of the image (the distortion is extrapolated there):");
    for (const std::string& cell : r.uncovered) std::printf(" %s", cell.c_str());
    std::printf("\n");
  }
  for (const std::string& w : r.weak) std::printf("poorly constrained: %s\n", w.c_str());
}

nlohmann::json Json(const CalibrationResult& r) {
  const CameraCalibration& c = r.camera;
  nlohmann::json views = nlohmann::json::array();
  for (const CalibrationView& v : r.views) {
    nlohmann::json j = {{"frame", v.frame}, {"used", v.used}, {"corners", v.corners}};
    if (v.used) j["rms_px"] = v.rms_px;
    else j["why_not"] = v.why_not;
    views.push_back(j);
  }
  return {{"model", CameraModelName(c.model)},
          {"width", c.width},
          {"height", c.height},
          {"rms_px", r.rms_px},
          {"views_used", r.views_used},
          {"frames", r.frames},
          {"intrinsics", {c.fx, c.fy, c.cx, c.cy}},
          {"distortion", c.distortion},
          {"uncovered", r.uncovered},
          {"weak", r.weak},
          {"views", views}};
}

}  // namespace

Command AddCalibrate(CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  app.add_option("INPUT", a->input, "A folder of images (or a dataset folder with images/) or a video file")->required();
  app.add_option("--board", a->board,
                 "The board: checkerboard:COLSxROWS:SQUARE_M, COLSxROWS its inner corners (e.g. checkerboard:9x6:0.04), "
                 "or charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT, COLSxROWS its squares as OpenCV's board generator "
                 "counts them (e.g. charuco:8x6:0.04:0.03:DICT_4X4_50)")
      ->required();
  app.add_option("--model", a->model, "pinhole | radtan (k1 k2 p1 p2, default) | equidistant (k1..k4) | fov (w)");
  app.add_option("--out", a->out, "The camera.yaml to write (default ./camera.yaml)");
  app.add_option("--json", a->json, "Also write the result as JSON: rms_px, views_used, intrinsics, distortion, ...");
  app.add_option("--max-views", a->max_views, "Most views calibrated with, picked to differ (default 40)");
  return [a] {
    CalibrationOptions options;
    options.board = BoardSpec::Parse(a->board, "--board");
    options.model = ParseCameraModel(a->model, "--model");
    if (a->max_views < kMinViews) throw InputError("--max-views must be at least " + std::to_string(kMinViews));
    options.max_views = a->max_views;
    const CalibrationResult r = Calibrate(a->input, options);
    PrintReport(r);
    CameraYaml yaml;
    yaml.camera = r.camera;
    WriteCameraYaml(a->out, yaml);
    std::printf("wrote %s\n", a->out.c_str());
    if (!a->json.empty()) WriteJson(a->json, Json(r));
    return 0;
  };
}

}  // namespace dsm::cli

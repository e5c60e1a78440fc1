// SPDX-License-Identifier: MIT
// dsm calibrate: a camera's geometric calibration from views of a checkerboard or a ChArUco board
// (calibration/calibrate.h), written as the camera.yaml dsm run reads.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "dsm/run/map_run.h"
#include "dsm/calibration/calibrate.h"
#include "dsm/io/calibration_io.h"
#include "dsm/run/line_delay_estimate.h"
#include "dsm/util/check.h"

namespace dsm::cli {

namespace {

struct CalibrateArgs {
  std::string input, board, model = "radtan", out = "camera.yaml", json, calib;
  int max_views = 40;
  bool line_delay = false;
};

// --line-delay: the rolling shutter's line delay of the camera that recorded INPUT
// (run/line_delay_estimate.h), written with its calibration.
int CalibrateLineDelay(const CalibrateArgs& a) {
  InputArgs video;
  video.calib = a.calib;
  Dataset dataset = OpenInput(a.input, GtArgs{}, video);
  dataset.line_delay_us = 0.0;
  dataset.line_delay_source = LineDelaySource::kUnknown;
  RunOptions options;
  options.quiet = true;
  const LineDelayEstimate e = EstimateLineDelay(dataset, options);
  std::printf("%s\n", LineDelayLine(e).c_str());
  CameraYaml yaml;
  yaml.camera = dataset.camera;
  if (dataset.size() >= 2)
    yaml.rate_hz = 1e9 * (dataset.size() - 1) / static_cast<double>(dataset.frames.back().t_ns - dataset.frames[0].t_ns);
  yaml.line_delay_us = e.line_delay_us;
  WriteCameraYaml(a.out, yaml);
  std::printf("wrote %s\n", a.out.c_str());
  if (!a.json.empty()) WriteJson(a.json, LineDelayJson(e));
  return 0;
}

void PrintReport(const CalibrationResult& r) {
  std::printf("%-7s %-8s %-8s\n", "frame", "corners", "rms px");
  for (const CalibrationView& v : r.views) {
    if (v.used && v.corners_dropped > 0)
      std::printf("%-7d %-8d %-8.3f %d corners left out as outliers\n", v.frame, v.corners, v.rms_px, v.corners_dropped);
    else if (v.used)
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
    if (v.used) j["rms_px"] = v.rms_px, j["corners_dropped"] = v.corners_dropped;
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
                 "counts them (e.g. charuco:8x6:0.04:0.03:DICT_4X4_50)");
  app.add_option("--model", a->model, "pinhole | radtan (k1 k2 p1 p2, default) | equidistant (k1..k4) | fov (w)");
  app.add_option("--out", a->out, "The camera.yaml to write (default ./camera.yaml)");
  app.add_option("--json", a->json, "Also write the result as JSON: rms_px, views_used, intrinsics, distortion, ...");
  app.add_option("--max-views", a->max_views, "Most views calibrated with, picked to differ (default 40)");
  app.add_flag("--line-delay", a->line_delay,
               "Instead of a board: the rolling shutter's line delay, estimated from INPUT, a recording of a scene "
               "(a dataset folder, or a video with --calib); writes its calibration with line_delay_us to --out");
  app.add_option("--calib", a->calib, "--line-delay on a video: the camera.yaml of the camera that recorded it");
  return [a] {
    if (a->line_delay) {
      if (!a->board.empty()) throw InputError("--line-delay and --board exclude each other");
      return CalibrateLineDelay(*a);
    }
    if (a->board.empty()) throw InputError("--board is required (or --line-delay, for a recording of a scene)");
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

// SPDX-License-Identifier: MIT
// A camera calibrated by dsm calibrate serves a run as well as the true calibration, for every lens
// model: `loop` (its first lap) is rendered through the model's lens (synth/lens_rays.h), boards
// are rendered through the same lens (board_render.h) and calibrated (calibrate.h) with the model,
// every pixel's ray of the found camera lands near its true pixel, and `loop` run from five start
// frames with each camera.yaml gives a median keyframe ATE within `ate_factor` of the true
// camera's: 1.1 for the pinhole and the FOV lens.
//
// Not yet for radtan (4.1x) and equidistant (2.0x); their bounds below catch a step back. The run
// is far more sensitive to an error in a lens's radial profile than to one in its focal length or
// principal point (on this scene, whose ATE is 2e-4 of the distances seen, a radial error of
// 0.01 px at the middle of the image's side and 0.05 px at its corner triples the ATE), and 24
// board views do not pin four distortion coefficients that closely.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dsm/calibration/board_render.h"
#include "dsm/calibration/calibrate.h"
#include "dsm/io/calibration_io.h"
#include "dsm/run/run.h"
#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/median.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

double KeyframeAte(const RunSummary& s) { return (*s.eval)["keyframes"]["ape"]["rmse"].get<double>(); }

// The largest distance, over a 40 px grid of the image, between a pixel and where the found camera
// projects the true camera's ray through it.
double WorstRayError(const CameraCalibration& truth, const CameraCalibration& found) {
  double worst_px = 0.0;
  for (int y = 0; y < truth.height; y += 40)
    for (int x = 0; x < truth.width; x += 40) {
      Eigen::Vector2d n;
      EXPECT_TRUE(truth.Unproject({double(x), double(y)}, &n));
      worst_px = std::max(worst_px, (found.Project({n.x(), n.y(), 1.0}) - Eigen::Vector2d(x, y)).norm());
    }
  return worst_px;
}

void ExpectRunsAsWithTheTrueCamera(CameraModel model, const std::string& board_spec, double worst_ray_px,
                                   double ate_factor) {
  const std::string name = CameraModelName(model);
  const fs::path work = testing::ScratchDir("calibrated_run_" + name);
  synth::SynthOptions scene;
  scene.scene = "loop";
  scene.frames = 300;
  scene.model = model;
  synth::WriteSequence(synth::MakeSequence(scene), scene, work / "true");
  const CameraYaml truth = ReadCameraYaml(work / "true" / "camera.yaml");
  ASSERT_EQ(truth.camera.model, model);

  const BoardSpec board = BoardSpec::Parse(board_spec, "test");
  WriteBoardSequence(work / "boards", truth.camera, board, 24, 3);
  CalibrationOptions options;
  options.board = board;
  options.model = model;
  const CalibrationResult found = Calibrate(work / "boards", options);
  std::printf("%s: found fx %.3f fy %.3f cx %.3f cy %.3f (true %.1f %.1f %.1f %.1f), rms %.3f px\n", name.c_str(),
              found.camera.fx, found.camera.fy, found.camera.cx, found.camera.cy, truth.camera.fx, truth.camera.fy,
              truth.camera.cx, truth.camera.cy, found.rms_px);
  const double worst_px = WorstRayError(truth.camera, found.camera);
  std::printf("%s: rays of the found camera within %.3f px of the true pixels\n", name.c_str(), worst_px);
  EXPECT_LT(worst_px, worst_ray_px);

  fs::copy(work / "true", work / "found", fs::copy_options::recursive);
  CameraYaml yaml = truth;
  yaml.camera = found.camera;
  WriteCameraYaml(work / "found" / "camera.yaml", yaml);
  RunOptions run;
  run.pace = Pace::kSequential;
  run.quiet = true;
  run.write_report = false;
  std::vector<double> with_true, with_found;
  for (const int start : {0, 2, 4, 6, 8}) {
    run.start = start;
    const std::string tag = std::to_string(start);
    const RunSummary t = RunDataset(OpenDataset(work / "true"), run, work / ("out_true_" + tag));
    const RunSummary f = RunDataset(OpenDataset(work / "found"), run, work / ("out_found_" + tag));
    ASSERT_TRUE(t.eval && f.eval);
    with_true.push_back(KeyframeAte(t));
    with_found.push_back(KeyframeAte(f));
    std::printf("%s, start %d: keyframe ATE %.3f mm with the true calibration, %.3f with the found one\n",
                name.c_str(), start, 1e3 * with_true.back(), 1e3 * with_found.back());
  }
  std::printf("%s: median keyframe ATE %.3f mm with the true calibration, %.3f with the found one\n", name.c_str(),
              1e3 * Median(with_true), 1e3 * Median(with_found));
  EXPECT_LE(Median(with_found), ate_factor * Median(with_true));
}

// The grid of rays reaches the image's corners: 0.1 px from a checkerboard (whose views keep the
// whole board in the image), 0.2 px from the ChArUco board (seen in part, up to the corners).
TEST(Calibrated, Pinhole) { ExpectRunsAsWithTheTrueCamera(CameraModel::kPinhole, "checkerboard:9x6:0.04", 0.1, 1.1); }

TEST(Calibrated, RadTan) { ExpectRunsAsWithTheTrueCamera(CameraModel::kRadTan, "checkerboard:9x6:0.04", 0.1, 6.0); }

TEST(Calibrated, Equidistant) {
  ExpectRunsAsWithTheTrueCamera(CameraModel::kEquidistant, "charuco:7x5:0.05:0.035:DICT_5X5_100", 0.2, 3.0);
}

TEST(Calibrated, Fov) { ExpectRunsAsWithTheTrueCamera(CameraModel::kFov, "checkerboard:9x6:0.04", 0.1, 1.1); }

}  // namespace
}  // namespace dsm

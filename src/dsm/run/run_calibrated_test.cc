// SPDX-License-Identifier: MIT
// A camera calibrated by dsm calibrate serves a run as well as the true calibration: the boards
// are rendered through `loop`'s camera (board_render.h) and calibrated (calibrate.h, pinhole);
// every pixel's ray of the found camera lies within 0.1 px of the true one's, and `loop` run from
// three start frames with each camera.yaml gives the same median keyframe ATE, within the runs'
// own spread (single runs of the same scene started a frame apart differ by up to 1.5x).
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

TEST(Calibrated, ARunWithTheFoundCameraIsAsGoodAsWithTheTrueOne) {
  const fs::path work = testing::ScratchDir("calibrated_run");
  synth::SynthOptions scene;
  scene.scene = "loop";
  synth::WriteSequence(synth::MakeSequence(scene), scene, work / "true");
  const CameraYaml truth = ReadCameraYaml(work / "true" / "camera.yaml");

  const BoardSpec board = BoardSpec::Parse("checkerboard:9x6:0.04", "test");
  WriteBoardSequence(work / "boards", truth.camera, board, 24, 3);
  CalibrationOptions options;
  options.board = board;
  options.model = CameraModel::kPinhole;
  const CalibrationResult found = Calibrate(work / "boards", options);
  std::printf("found fx %.3f fy %.3f cx %.3f cy %.3f (true %.1f %.1f %.1f %.1f), rms %.3f px\n", found.camera.fx,
              found.camera.fy, found.camera.cx, found.camera.cy, truth.camera.fx, truth.camera.fy, truth.camera.cx,
              truth.camera.cy, found.rms_px);

  fs::copy(work / "true", work / "found", fs::copy_options::recursive);
  CameraYaml yaml = truth;
  yaml.camera = found.camera;
  WriteCameraYaml(work / "found" / "camera.yaml", yaml);
  double worst_px = 0.0;
  for (int y = 0; y < truth.camera.height; y += 40)
    for (int x = 0; x < truth.camera.width; x += 40) {
      Eigen::Vector2d n;
      ASSERT_TRUE(truth.camera.Unproject({double(x), double(y)}, &n));
      worst_px = std::max(worst_px, (found.camera.Project({n.x(), n.y(), 1.0}) - Eigen::Vector2d(x, y)).norm());
    }
  EXPECT_LT(worst_px, 0.1);
  RunOptions run;
  run.pace = Pace::kSequential;
  run.quiet = true;
  run.write_report = false;
  std::vector<double> with_true, with_found;
  for (const int start : {0, 2, 4}) {
    run.start = start;
    const std::string tag = std::to_string(start);
    const RunSummary t = RunDataset(OpenDataset(work / "true"), run, work / ("out_true_" + tag));
    const RunSummary f = RunDataset(OpenDataset(work / "found"), run, work / ("out_found_" + tag));
    ASSERT_TRUE(t.eval && f.eval);
    with_true.push_back(KeyframeAte(t));
    with_found.push_back(KeyframeAte(f));
    std::printf("start %d: keyframe ATE %.3f mm with the true calibration, %.3f with the found one\n", start,
                1e3 * with_true.back(), 1e3 * with_found.back());
  }
  EXPECT_LE(Median(with_found), 1.25 * Median(with_true));
}

}  // namespace
}  // namespace dsm

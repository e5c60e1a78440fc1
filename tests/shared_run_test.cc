// SPDX-License-Identifier: MIT
// End to end on the shared sequences, both modes:
//   EuRoC MH01 frames: initialised within 20 frames, every later frame tracked, keyframe RMS ATE
//   (Sim(3)) <= 5 mm for DSM and <= 12 mm for DSM-SW.
//   Path-traced room walk (blender_room_s3), from five start frames: every frame after the start
//   tracked, the medians DSM <= 1.15 mm and below DSM-SW, DSM-SW <= 2 mm (its window: N_t + N_c
//   temporal keyframes), after a final global bundle adjustment <= 1 mm and below DSM's, and the
//   map adjusted from the true poses (--truth-ba) <= 1 mm from them. The room is where a pillar
//   passes close to the camera (the occlusion test), the young map's scale drifts without its
//   bundle adjustments, points on faint texture bias the map (the candidates' contrast floor) and
//   the render noise biases bilinear residuals (the B-spline).
//   EuRoC frames with defects spliced in (15 black frames, 15 of noise, a corrupt file and a hand
//   over the lens for 41 frames): no black or noise frame, nor one the hand covers for three
//   quarters or more, is tracked, and none of them nor a half-covered one becomes a keyframe;
//   tracking is regained within 5 frames of each episode's end by relocalisation in the same map,
//   every frame after the last defect is tracked, and the keyframe ATE stays <= 6 mm. The room
//   with the same defects: the same, and its keyframe ATE <= 3.5 mm.
//   Both laps of the room as one recording, from frames 4 and 8: the keyframe ATE <= 2 mm (no loop
//   bends a map that is right).
//   Neither calibration says anything of the shutter: the EuRoC runs and one run of the room
//   estimate the line delay (a global shutter: under 3 us per row, and the room's run the same as
//   the one told 0); the room's other runs are told its global shutter (dsm run --line-delay-us 0).
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dsm/io/euroc_copy.h"
#include "dsm/run/defect_checks.h"
#include "dsm/run/run.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/median.h"

namespace dsm {
namespace {

// The shared `name`, its shutter told global (as dsm run --line-delay-us 0 tells it).
Dataset TakenGlobal(Dataset dataset) {
  dataset.line_delay_us = 0.0;
  dataset.line_delay_source = LineDelaySource::kOption;
  return dataset;
}

// A sequential run of `mode` from frame `start` (options.global_ba and truth_ba as given), after
// checking that it initialised within `max_init_frames` of its start, tracked every frame after
// and was evaluated.
RunSummary CheckedRun(const Dataset& dataset, const std::string& name, MapMode mode, int start, int max_init_frames,
                      RunOptions options = {}) {
  options.pace = Pace::kSequential;
  options.quiet = true;
  options.start = start;
  options.system.mode = mode;
  const std::string label =
      name + " " + (mode == MapMode::kFull ? "dsm" : "sw") + (start > 0 ? " from frame " + std::to_string(start) : "");
  const RunSummary s = RunDataset(dataset, options, testing::ScratchDir("shared_run_" + name));
  std::printf("%s: %s (PBA %.0f ms/KF)\n", label.c_str(), s.line.c_str(),
              s.stats["timing_ms"]["pba"]["mean"].get<double>());
  const int init = s.stats["initialized_at_frame"];
  EXPECT_LE(init, start + max_init_frames) << label;
  EXPECT_GE(s.stats["frames_tracked"].get<int>(), s.stats["frames"].get<int>() - (init - start)) << label;
  EXPECT_TRUE(s.eval.has_value()) << label;
  return s;
}

// Both modes' runs from the first frame (CheckedRun).
std::map<MapMode, RunSummary> RunBothModes(const std::string& name, int max_init_frames) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / name);
  std::map<MapMode, RunSummary> runs;
  for (const MapMode mode : {MapMode::kSlidingWindow, MapMode::kFull})
    runs.emplace(mode, CheckedRun(dataset, name, mode, 0, max_init_frames));
  return runs;
}

// Keyframe RMS ATE (m); a failed evaluation counts as far off.
double Ate(const RunSummary& s) { return s.eval ? (*s.eval)["keyframes"]["ape"]["rmse"].get<double>() : 1e9; }

TEST(SharedRun, EurocMeetsTheAccuracyTargets) {
  const auto runs = RunBothModes("euroc_mh01_shake", 20);
  for (const auto& [mode, s] : runs) {
    EXPECT_EQ(s.stats["line_delay_source"], "estimated");
    EXPECT_LT(s.stats["line_delay_us"].get<double>(), 3.0);
  }
  EXPECT_LE(Ate(runs.at(MapMode::kFull)), 0.005);
  EXPECT_FALSE(runs.at(MapMode::kFull).stats["contrast_floor"].get<bool>());  // A camera's noise: 0.47.
  EXPECT_EQ(runs.at(MapMode::kFull).stats["interpolation"].get<std::string>(), "bilinear");
  EXPECT_FALSE(runs.at(MapMode::kFull).stats["texture_loss"].get<bool>());  // A camera's noise: off.
  EXPECT_LE(Ate(runs.at(MapMode::kSlidingWindow)), 0.012);
}

// The room walk from the first five of the twelve start frames the README reports (0, 2, ... 8):
// one run is one draw of a chaotic system (its keyframe ATE ranges 0.8-2.2 mm with the start
// alone), the median of five is not. DSM's runs also bundle-adjust the whole map at the end
// (--global-ba) and adjust it again from the true poses (--truth-ba); the ATE before the global
// adjustment is that of a plain run. The young map's bundle adjustments
// (SystemOptions::young_map_ba_last) at 10, 20 and 40 keyframes keep the walk's scale from
// drifting. The room's render noise (4.7 grey levels) turns the candidates' contrast floor, the
// B-spline residuals and (DSM only) the texture-loss test in the fits on.
TEST(SharedRun, RoomWalkKeepsItsScale) {
  const Dataset dataset = TakenGlobal(OpenDataset(testing::SharedDataDir() / "blender_room_s3"));
  std::vector<double> dsm, sw, global, truth;
  for (const int start : {0, 2, 4, 6, 8}) {
    for (const MapMode mode : {MapMode::kFull, MapMode::kSlidingWindow}) {
      RunOptions options;
      options.global_ba = options.truth_ba = mode == MapMode::kFull;
      const RunSummary s = CheckedRun(dataset, "blender_room_s3", mode, start, 20, options);
      EXPECT_TRUE(s.stats["contrast_floor"].get<bool>()) << start;
      EXPECT_EQ(s.stats["interpolation"].get<std::string>(), "bspline") << start;
      EXPECT_EQ(s.stats["texture_loss"].get<bool>(), mode == MapMode::kFull) << start;
      ASSERT_TRUE(s.eval.has_value()) << start;
      if (mode == MapMode::kSlidingWindow) {
        sw.push_back(Ate(s));
        continue;
      }
      dsm.push_back((*s.eval)["keyframes_before_global_ba"]["ape"]["rmse"].get<double>());
      global.push_back(Ate(s));
      truth.push_back((*s.eval)["keyframes_truth_ba"]["ape"]["rmse"].get<double>());
      if (start == 0) {
        std::vector<int> young;
        for (const auto& k : s.stats["per_keyframe"])
          if (k.contains("young_map_ba")) young.push_back(k["young_map_ba"]["keyframes"].get<int>());
        EXPECT_EQ(young, (std::vector<int>{10, 20, 40}));
      }
    }
  }
  std::printf("blender_room_s3 medians of five starts: dsm %.2f mm, sw %.2f, --global-ba %.2f, --truth-ba %.2f\n",
              1e3 * Median(dsm), 1e3 * Median(sw), 1e3 * Median(global), 1e3 * Median(truth));
  EXPECT_LE(Median(dsm), 0.00115);
  EXPECT_LE(Median(sw), 0.002);
  EXPECT_LT(Median(dsm), Median(sw));
  // A final global bundle adjustment still improves the walk (the window holds old keyframes
  // fixed), and the map's own optimum lies near the true poses.
  EXPECT_LE(Median(global), 0.001);
  EXPECT_LT(Median(global), Median(dsm));
  EXPECT_LE(Median(truth), 0.001);
}

// The test suite's defects spliced into the shared recording `name` (in a scratch folder), run
// sequentially in each of `modes`: each defect costs its frames only (defect_checks.h), the corrupt
// file is skipped, and the keyframe ATE is at most `max_ate` (m). Returns the runs, in that order.
std::vector<RunSummary> ExpectDefectsCostTheirFramesOnlyIn(const std::string& name, const std::vector<MapMode>& modes,
                                                           double max_ate) {
  const std::filesystem::path src = testing::SharedDataDir() / name;
  const std::filesystem::path dir = testing::ScratchDir("shared_run_defects_" + name);
  WriteEurocCopy(src, dir / "data", OpenDataset(src).size(), {},
                          "black:100-114,noise:160-174,corrupt:200,cover:240-280");
  const Dataset dataset = TakenGlobal(OpenDataset(dir / "data"));
  std::vector<RunSummary> runs;
  for (const MapMode mode : modes) {
    const std::string label = name + (mode == MapMode::kFull ? " dsm" : " sw");
    const std::filesystem::path out = dir / (mode == MapMode::kFull ? "out_dsm" : "out_sw");
    RunOptions options;
    options.pace = Pace::kSequential;
    options.quiet = true;
    options.system.mode = mode;
    const RunSummary& s = runs.emplace_back(RunDataset(dataset, options, out));
    std::printf("%s with defects: %s\n", label.c_str(), s.line.c_str());
    EXPECT_EQ(s.stats["frames_skipped"], 1) << label;
    testing::ExpectDefectsCostTheirFramesOnly(dataset, s, out, {{100, 114}, {160, 174}, {240, 280, true}}, label);
    EXPECT_TRUE(s.eval.has_value()) << label;
    if (s.eval) {
      EXPECT_LE((*s.eval)["keyframes"]["ape"]["rmse"].get<double>(), max_ate) << label;
    }
  }
  return runs;
}

TEST(SharedRun, EurocWithDefectsRelocalisesInTheSameMap) {
  ExpectDefectsCostTheirFramesOnlyIn("euroc_mh01_shake", {MapMode::kSlidingWindow, MapMode::kFull}, 0.006);
}

// The path-traced room with the same defects (a fast walk, 34 mm per frame): caught, regained in
// the same map and no keyframe of a bad frame, as on EuRoC; the keyframe ATE (2.74 mm, against 0.94
// clean) is bounded where a gap of 15-19 frames left it over five spans, cut or black (1.0-2.7 mm,
// README: The path-traced room with defects), not at the 1.5x of the clean run.
TEST(SharedRun, RoomWithDefectsRelocalisesInTheSameMap) {
  const std::vector<RunSummary> runs = ExpectDefectsCostTheirFramesOnlyIn("blender_room_s3", {MapMode::kFull}, 0.0035);
  EXPECT_EQ(runs[0].stats["relocalisations"], 3);
}

// Both laps of the room walk as one recording: a EuRoC folder in `dir` linking lap 1's images and
// then lap 2's, with both laps' ground truth.
Dataset JoinedLaps(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const fs::path cam = dir / "mav0" / "cam0", gt = dir / "mav0" / "state_groundtruth_estimate0";
  fs::remove_all(dir);
  fs::create_directories(cam / "data");
  fs::create_directories(gt);
  const fs::path lap1 = testing::SharedDataDir() / "blender_room_s3", lap2 = testing::SharedDataDir() / "blender_room_s3_lap2";
  fs::copy_file(lap1 / "mav0" / "cam0" / "sensor.yaml", cam / "sensor.yaml");
  std::ofstream images(cam / "data.csv"), poses(gt / "data.csv");
  for (const fs::path& lap : {lap1, lap2}) {
    for (const auto& png : fs::directory_iterator(lap / "mav0" / "cam0" / "data"))
      fs::create_symlink(png.path(), cam / "data" / png.path().filename());
    for (const auto& [from, to] : {std::pair{lap / "mav0" / "cam0" / "data.csv", &images},
                                   std::pair{lap / "mav0" / "state_groundtruth_estimate0" / "data.csv", &poses}}) {
      std::ifstream in(from);
      for (std::string line; std::getline(in, line);)
        if (!line.empty() && (line[0] != '#' || lap == lap1)) *to << line << "\n";
    }
  }
  images.close(), poses.close();
  return TakenGlobal(OpenDataset(dir));
}

// Both laps as one recording, from two start frames: the second lap passes a few centimetres from
// the first, whose map is right to about a millimetre, so nothing needs closing; a loop verified
// against a view its candidate only resembles (an alignment at several times the keyframe's error
// scale) bends that map by degrees, to tens of millimetres.
TEST(SharedRun, TheRoomsSecondLapBendsNothing) {
  const Dataset dataset = JoinedLaps(testing::ScratchDir("shared_run_two_laps") / "sequence");
  ASSERT_EQ(dataset.frames.size(), 600u);
  for (const int start : {4, 8}) {
    const RunSummary s = CheckedRun(dataset, "room_two_laps", MapMode::kFull, start, 20);
    EXPECT_LE(Ate(s), 0.002) << "from frame " << start;
  }
}

// The room's camera, a global shutter the calibration does not mention, estimated as one: the run
// is the run told so, keyframe for keyframe.
TEST(SharedRun, TheRoomsShutterIsEstimatedGlobal) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / "blender_room_s3");
  ASSERT_EQ(dataset.line_delay_source, LineDelaySource::kUnknown);
  const RunSummary estimated = CheckedRun(dataset, "blender_room_s3", MapMode::kFull, 0, 20);
  EXPECT_EQ(estimated.stats["line_delay_source"], "estimated");
  EXPECT_LT(estimated.stats["line_delay_us"].get<double>(), 3.0);
  const RunSummary told = CheckedRun(TakenGlobal(dataset), "blender_room_s3", MapMode::kFull, 0, 20);
  EXPECT_EQ(told.stats["line_delay_source"], "option");
  EXPECT_NEAR(Ate(estimated), Ate(told), 0.03 * Ate(told));
}

}  // namespace
}  // namespace dsm

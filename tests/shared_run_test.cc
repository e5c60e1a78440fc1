// SPDX-License-Identifier: MIT
// End to end on the shared sequences, both modes:
//   EuRoC MH01 frames: initialised within 20 frames, every later frame tracked, keyframe RMS ATE
//   (Sim(3)) <= 5 mm for DSM and <= 12 mm for DSM-SW.
//   Path-traced room walk (blender_room_s3): every frame after the start tracked, DSM <= 1.5 mm
//   and below DSM-SW, DSM-SW <= 4 mm (its window: N_t + N_c temporal keyframes). Before
//   occlusions were handled DSM's scale collapsed there as a pillar passed close to the camera
//   (1066 mm); before the young map's bundle adjustments its scale drifted (3.64 mm); before the
//   candidates' contrast floor its points on faint texture biased the map (1.83 mm, DSM-SW 5.89).
//   A final global bundle adjustment still improves the walk, to <= 1.2 mm (measured 1.12 ->
//   0.96 mm), and the map adjusted from the true poses (--truth-ba) ends <= 1.2 mm from them
//   (0.99 mm; 1.44 without the contrast floor).
//   EuRoC frames with defects spliced in (15 black frames, 15 of noise, a corrupt file and a hand
//   over the lens for 41 frames): no black or noise frame, nor one the hand covers for three
//   quarters or more, is tracked, and none of them nor a half-covered one becomes a keyframe;
//   tracking is regained within 5 frames of each episode's end by relocalisation in the same map,
//   every frame after the last defect is tracked, and the keyframe ATE stays <= 6 mm.
#include <map>

#include <gtest/gtest.h>

#include "dsm/io/euroc_copy.h"
#include "dsm/run/defect_checks.h"
#include "dsm/run/run.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

// Both modes' runs, after checking initialisation and tracking.
std::map<MapMode, RunSummary> RunBothModes(const std::string& name, int max_init_frame) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / name);
  std::map<MapMode, RunSummary> runs;
  for (const MapMode mode : {MapMode::kSlidingWindow, MapMode::kFull}) {
    RunOptions options;
    options.pace = Pace::kSequential;
    options.quiet = true;
    options.system.mode = mode;
    const RunSummary s = RunDataset(dataset, options, testing::ScratchDir("shared_run_" + name));
    std::printf("%s %s: %s (PBA %.0f ms/KF)\n", name.c_str(), mode == MapMode::kFull ? "dsm" : "sw", s.line.c_str(),
                s.stats["timing_ms"]["pba"]["mean"].get<double>());
    const int init = s.stats["initialized_at_frame"];
    EXPECT_LE(init, max_init_frame);
    EXPECT_GE(s.stats["frames_tracked"].get<int>(), s.stats["frames"].get<int>() - init);
    EXPECT_TRUE(s.eval.has_value());
    runs.emplace(mode, s);
  }
  return runs;
}

// Keyframe RMS ATE (m); a failed evaluation counts as far off.
double Ate(const RunSummary& s) { return s.eval ? (*s.eval)["keyframes"]["ape"]["rmse"].get<double>() : 1e9; }

TEST(SharedRun, EurocMeetsTheAccuracyTargets) {
  const auto runs = RunBothModes("euroc_mh01_shake", 20);
  EXPECT_LE(Ate(runs.at(MapMode::kFull)), 0.005);
  EXPECT_FALSE(runs.at(MapMode::kFull).stats["contrast_floor"].get<bool>());  // A camera's noise: 0.47.
  EXPECT_LE(Ate(runs.at(MapMode::kSlidingWindow)), 0.012);
}

// The young map's bundle adjustments (SystemOptions::young_map_ba_last) at 10, 20 and 40
// keyframes keep the walk's scale from drifting: 3.64 mm without them. The room's render noise
// (4.7 grey levels) turns the candidates' contrast floor on.
TEST(SharedRun, RoomWalkKeepsItsScale) {
  const auto runs = RunBothModes("blender_room_s3", 20);
  const RunSummary& dsm = runs.at(MapMode::kFull);
  EXPECT_LE(Ate(dsm), 0.0015);
  EXPECT_LE(Ate(runs.at(MapMode::kSlidingWindow)), 0.004);
  EXPECT_TRUE(dsm.stats["contrast_floor"].get<bool>());
  EXPECT_LT(Ate(dsm), Ate(runs.at(MapMode::kSlidingWindow)));
  std::vector<int> young;
  for (const auto& k : dsm.stats["per_keyframe"])
    if (k.contains("young_map_ba")) young.push_back(k["young_map_ba"]["keyframes"].get<int>());
  EXPECT_EQ(young, (std::vector<int>{10, 20, 40}));
}

TEST(SharedRun, RoomWalkGlobalBundleAdjustmentMakesTheLapConsistent) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / "blender_room_s3");
  RunOptions options;
  options.pace = Pace::kSequential;
  options.quiet = true;
  options.global_ba = true;
  options.truth_ba = true;
  const RunSummary s = RunDataset(dataset, options, testing::ScratchDir("shared_run_room_global_ba"));
  std::printf("blender_room_s3 dsm --global-ba: %s\n", s.line.c_str());
  ASSERT_TRUE(s.eval.has_value());
  const double before = (*s.eval)["keyframes_before_global_ba"]["ape"]["rmse"].get<double>();
  const double after = (*s.eval)["keyframes"]["ape"]["rmse"].get<double>();
  EXPECT_LE(after, 0.0012);
  EXPECT_LT(after, before);
  EXPECT_LE((*s.eval)["keyframes_truth_ba"]["ape"]["rmse"].get<double>(), 0.0012);
}

TEST(SharedRun, EurocWithDefectsRelocalisesInTheSameMap) {
  const Dataset clean = OpenDataset(testing::SharedDataDir() / "euroc_mh01_shake");
  const std::filesystem::path dir = testing::ScratchDir("shared_run_euroc_defects");
  testing::WriteEurocCopy(testing::SharedDataDir() / "euroc_mh01_shake", dir / "data", clean.size(), {},
                          "black:100-114,noise:160-174,corrupt:200,cover:240-280");
  const Dataset dataset = OpenDataset(dir / "data");
  for (const MapMode mode : {MapMode::kSlidingWindow, MapMode::kFull}) {
    const std::string name = mode == MapMode::kFull ? "dsm" : "sw";
    RunOptions options;
    options.pace = Pace::kSequential;
    options.quiet = true;
    options.system.mode = mode;
    const RunSummary s = RunDataset(dataset, options, dir / ("out_" + name));
    std::printf("euroc with defects %s: %s\n", name.c_str(), s.line.c_str());
    EXPECT_EQ(s.stats["frames_skipped"], 1) << name;
    testing::ExpectDefectsCostTheirFramesOnly(dataset, s, dir / ("out_" + name),
                                              {{100, 114}, {160, 174}, {240, 280, true}}, name);
    ASSERT_TRUE(s.eval.has_value());
    EXPECT_LE((*s.eval)["keyframes"]["ape"]["rmse"].get<double>(), 0.006) << name;
  }
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// Two sessions in one place through a map file (RunOptions::save_map, RunOptions::load_map):
// `loop` (a furnished room walked around twice, rendered at 320x240) split at its half. Session 1,
// the first lap, is saved (adjusted whole first). Session 2, the second lap,
// loads it: it relocalises in the loaded map within 3 frames of its start, writes only its own
// keyframes, and they lie in session 1's frame and scale: scored with session 1's Sim(3) alignment
// (none of their own), their ATE is within 1.5x that of one run over both laps. It re-uses the map: its points added are under a quarter of those session 1 made, and
// its keyframes of places lap 1 mapped are culled. The loaded keyframes stay where the file has them. A map file read and written again is the same
// file, and session 2 run twice writes the same file (sequential). Session 2 localising in the map
// instead (RunOptions::localize) leaves it byte for byte as loaded. The report tells the
// loaded map's points from the added ones. A map of another camera is refused, naming the file.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "dsm/eval/metrics.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/mapfile/map_file.h"
#include "dsm/report/report.h"
#include "dsm/run/run.h"
#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

fs::path Render(const std::string& name, const synth::SynthOptions& options) {
  const fs::path dir = testing::ScratchDir(name) / "sequence";
  synth::WriteSequence(synth::MakeSequence(options), options, dir);
  return dir;
}

std::string Bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

RunOptions Session(int start, int end) {
  RunOptions options;
  options.pace = Pace::kSequential;
  options.quiet = true;
  options.write_report = false;
  options.start = start;
  options.end = end;
  return options;
}

double KeyframeAte(const RunSummary& s) { return (*s.eval)["keyframes"]["ape"]["rmse"].get<double>(); }

TEST(Sessions, TheSecondLapRelocalisesInTheSavedMapAndKeepsItsFrame) {
  synth::SynthOptions synth;
  synth.scene = "loop";
  synth.width = 320;
  synth.height = 240;
  const fs::path dir = Render("sessions_loop", synth);
  const fs::path work = dir.parent_path();
  const Dataset dataset = OpenDataset(dir);
  const int half = static_cast<int>(dataset.size()) / 2;

  const RunSummary both = RunDataset(dataset, Session(0, -1), work / "both");
  RunOptions first = Session(0, half);
  first.save_map = work / "lap1.dsmmap";
  const RunSummary s1 = RunDataset(dataset, first, work / "lap1");
  RunOptions second = Session(half, -1);
  second.load_map = first.save_map;
  second.save_map = work / "lap2.dsmmap";
  const RunSummary s2 = RunDataset(dataset, second, work / "lap2");
  std::printf("both laps: %s\nlap 1: %s\nlap 2: %s\n", both.line.c_str(), s1.line.c_str(), s2.line.c_str());

  ASSERT_TRUE(both.eval && s1.eval && s2.eval);
  EXPECT_EQ(s2.stats["map_loaded"]["keyframes"], s1.stats["keyframes"]);
  EXPECT_EQ(s2.stats["map_loaded"]["points"], s1.stats["map_points"]);
  ASSERT_TRUE(s2.stats["relocalised_in_loaded_map_at_frame"].is_number());
  EXPECT_LE(s2.stats["relocalised_in_loaded_map_at_frame"].get<int>(), half + 3);
  EXPECT_GE(s2.stats["frames_tracked"].get<int>(), 0.98 * (dataset.size() - half));
  EXPECT_LE(s2.stats["points_added"].get<int>(), 0.25 * s1.stats["points_created"].get<int>());

  // keyframes.tum holds session 2's keyframes alone, scored in session 1's frame and scale.
  const Trajectory keyframes = ReadTrajectory(work / "lap2" / "keyframes.tum", TrajectoryFormat::kTum);
  EXPECT_EQ(static_cast<int>(keyframes.size()), s2.stats["keyframes_added"].get<int>());
  EXPECT_GE(keyframes.stamps_ns.front(), dataset.frames[half].t_ns);
  EvalOptions eval;
  eval.fixed_alignment = AlignmentFromJson(*s1.eval, "session 1");
  const double ate = Evaluate(dataset.ground_truth, keyframes, eval).ape.rmse;
  std::printf("lap 2 in lap 1's alignment: keyframe ATE %.2f mm (both laps in one run: %.2f mm)\n", 1000 * ate,
              1000 * KeyframeAte(both));
  EXPECT_LE(ate, 1.5 * KeyframeAte(both));

  // The report draws the loaded map's points apart (they come first) and numbers session 2's
  // keyframes after the loaded ones.
  const nlohmann::json report = ReportData(work / "lap2");
  const int loaded_keyframes = s1.stats["keyframes"].get<int>();
  EXPECT_GT(report["maps"][0]["points"]["loaded"].get<int>(), 0.5 * s1.stats["map_points"].get<int>());
  EXPECT_LT(report["maps"][0]["points"]["loaded"].get<int>(), report["maps"][0]["points"]["count"].get<int>());
  EXPECT_EQ(report["maps"][0]["keyframes"][0]["id"].get<int>(), loaded_keyframes);
  EXPECT_EQ(report["summary"]["map_loaded"]["keyframes"].get<int>(), loaded_keyframes);

  // The loaded keyframes are where session 1 left them; session 2's follow.
  const MapFile saved1 = ReadMapFile(first.save_map), saved2 = ReadMapFile(second.save_map);
  ASSERT_EQ(saved2.maps.size(), 1u);
  const Map& m1 = saved1.maps[0].map;
  const Map& m2 = saved2.maps[0].map;
  // Session 2's own keyframes of places lap 1 mapped are culled: the map grows by the rest.
  EXPECT_GT(s2.stats["keyframes_culled"].get<int>(), 0);
  EXPECT_GT(both.stats["keyframes_culled"].get<int>(), 0);
  ASSERT_EQ(m2.NumKeyframes(), m1.NumKeyframes() + s2.stats["keyframes_kept"].get<int>());
  for (int k = 0; k < m1.NumKeyframes(); ++k)
    EXPECT_EQ(m1.keyframe(k).cam_from_world.Matrix(), m2.keyframe(k).cam_from_world.Matrix()) << "keyframe " << k;

  // Read and written again: the same bytes. Session 2 again: the same map file.
  WriteMapFile(work / "lap1_again.dsmmap", saved1);
  EXPECT_EQ(Bytes(work / "lap1_again.dsmmap"), Bytes(first.save_map));
  RunOptions again = second;
  again.save_map = work / "lap2_again.dsmmap";
  RunDataset(dataset, again, work / "lap2_again");
  EXPECT_EQ(Bytes(again.save_map), Bytes(second.save_map));

  // Localising in the map (--localize): the same lap tracked in session 1's frame and scale as
  // closely, the map file written after it the same bytes as the one loaded, and the keyframes made
  // on the way retired as the camera sees the map again (all but the window's few).
  RunOptions localize = second;
  localize.localize = true;
  localize.save_map = work / "lap1_localized.dsmmap";
  const RunSummary s3 = RunDataset(dataset, localize, work / "localized");
  std::printf("lap 2 localised: %s\n", s3.line.c_str());
  EXPECT_EQ(Bytes(localize.save_map), Bytes(first.save_map));
  ASSERT_TRUE(s3.stats["relocalised_in_loaded_map_at_frame"].is_number());
  EXPECT_LE(s3.stats["relocalised_in_loaded_map_at_frame"].get<int>(), half + 3);
  EXPECT_TRUE(s3.stats["localize"].get<bool>());
  const int made = s3.stats["keyframes_added"].get<int>();
  EXPECT_GE(s3.stats["keyframes_retired"].get<int>(), made - 2 * second.system.window.temporal_keyframes);
  const Trajectory localized = ReadTrajectory(work / "localized" / "keyframes.tum", TrajectoryFormat::kTum);
  EXPECT_EQ(static_cast<int>(localized.size()), made);
  const double localized_ate = Evaluate(dataset.ground_truth, localized, eval).ape.rmse;
  std::printf("lap 2 localised in lap 1's alignment: keyframe ATE %.2f mm\n", 1000 * localized_ate);
  EXPECT_LE(localized_ate, 1.5 * KeyframeAte(both));

  // A recording of another camera (half the size) cannot use the map.
  synth::SynthOptions small = synth;
  small.frames = 10;
  small.width = 160;
  small.height = 128;
  const fs::path other = Render("sessions_small", small);
  RunOptions load = Session(0, -1);
  load.load_map = first.save_map;
  try {
    RunDataset(OpenDataset(other), load, other.parent_path() / "out");
    ADD_FAILURE() << "a map of another camera was loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(first.save_map.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("another camera"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dsm

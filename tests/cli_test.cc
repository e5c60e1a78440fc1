// SPDX-License-Identifier: MIT
// The `dsm` command line as a user runs it: outputs, and clear errors with exit code 2 for bad
// input (never a crash).
#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/euroc_copy.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/synth/lens_rays.h"
#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"
#include "cli.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::SharedDataDir;
using testing::Contains;
using testing::Result;
using testing::RunDsm;
using testing::WriteText;


TEST(Cli, InfoDescribesTheSharedEurocData) {
  const Result r = RunDsm("info " + (SharedDataDir() / "euroc_mh01_shake").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "format:       euroc"));
  EXPECT_TRUE(Contains(r.output, "frames:       340"));
  EXPECT_TRUE(Contains(r.output, "resolution:   752x480"));
  EXPECT_TRUE(Contains(r.output, "camera model: radtan"));
  EXPECT_TRUE(Contains(r.output, "1403636584.763555584"));
  EXPECT_TRUE(Contains(r.output, "ground truth: yes"));
  EXPECT_TRUE(Contains(r.output, "photometric:  no"));
}

// The shared EuRoC ground truth, read as documented (body poses x T_BS, Hamilton quaternions),
// fits its images to ~0.3 px; the other readings miss them by pixels to tens of pixels.
TEST(Cli, GtCheckFindsTheDocumentedReadingOnTheSharedData) {
  const fs::path dir = ScratchDir("cli_gt_check");
  const Result r = RunDsm("gt-check " + (SharedDataDir() / "euroc_mh01_shake").string() + " --pairs 30 --json " +
                          (dir / "gt.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "images agree best with: body-hamilton")) << r.output;
  std::ifstream in(dir / "gt.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["readings"].size(), 4u);
  EXPECT_EQ(j["best"], "body-hamilton");
  for (const auto& row : j["readings"]) {
    if (row["ground_truth"] == "body-hamilton") {
      EXPECT_LT(row["median_px"].get<double>(), 0.5);
    } else {
      EXPECT_GT(row["median_px"].get<double>(), 2.0) << row;
    }
  }
  const Result info = RunDsm("info " + (SharedDataDir() / "euroc_mh01_shake").string());
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_TRUE(Contains(info.output, "ground truth: yes (380 camera poses"));
}

// Files from other sources store camera poses, or JPL quaternions: gt-check names the reading a
// copy of the shared frames needs, and `dsm info --gt-out` with that reading writes the same camera
// poses as the documented file does.
TEST(Cli, GtCheckNamesTheReadingOfOtherFiles) {
  const fs::path shared = SharedDataDir() / "euroc_mh01_shake";
  const fs::path dir = ScratchDir("cli_gt_readings");
  ASSERT_EQ(RunDsm("info " + shared.string() + " --gt-out " + (dir / "documented.tum").string()).code, 0);
  const Trajectory documented = ReadTrajectory(dir / "documented.tum", TrajectoryFormat::kTum);
  ASSERT_EQ(documented.size(), 380u);
  for (const auto& [frame, quaternion] : {std::pair{"camera", "jpl"}, std::pair{"body", "jpl"}}) {
    const std::string name = std::string(frame) + "-" + quaternion;
    const GroundTruthConvention reading{ParseGtFrame(frame, "frame"), ParseGtQuaternion(quaternion, "quaternion")};
    WriteEurocCopy(shared, dir / name, 120, reading);
    const Result r = RunDsm("gt-check " + (dir / name).string() + " --pairs 20");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(Contains(r.output, "images agree best with: " + name)) << r.output;
    const std::string read = " --gt-frame " + std::string(frame) + " --gt-quaternion " + quaternion;
    const Result info = RunDsm("info " + (dir / name).string() + read + " --gt-out " + (dir / (name + ".tum")).string());
    ASSERT_EQ(info.code, 0) << info.output;
    EXPECT_TRUE(Contains(info.output, "ground truth written to"));
    const Trajectory as_read = ReadTrajectory(dir / (name + ".tum"), TrajectoryFormat::kTum);
    ASSERT_EQ(as_read.size(), documented.size());
    for (size_t i = 0; i < as_read.size(); i += 19) {
      EXPECT_LT((as_read.poses[i].Matrix() - documented.poses[i].Matrix()).norm(), 1e-6) << name << " row " << i;
    }
  }
}

TEST(Cli, EvalWritesTheJsonContract) {
  const fs::path dir = ScratchDir("cli_eval");
  const fs::path traj = SharedDataDir() / "trajectories";
  const Result r = RunDsm("eval --ref " + (traj / "KITTI_00_gt.txt").string() + " --est " +
                       (traj / "KITTI_00_ORB.txt").string() + " --align sim3 --rpe-delta 100 --rpe-unit f --json " +
                       (dir / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(dir / "out.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key : {"rmse", "mean", "median", "std", "min", "max"}) {
    EXPECT_TRUE(j["ape"].contains(key)) << key;
    EXPECT_TRUE(j["rpe"].contains(key)) << key;
  }
  EXPECT_EQ(j["pairs"], 4541);
  EXPECT_EQ(j["rpe"]["pairs"], 45);  // indices 0, 100, ..., 4500
  EXPECT_GT(j["scale"].get<double>(), 0.0);
}

TEST(Cli, SynthOutputIsADatasetThatInfoReads) {
  const fs::path dir = ScratchDir("cli_synth");
  const Result r = RunDsm("synth --scene shake --out " + (dir / "seq").string() +
                       " --frames 5 --width 160 --height 120 --vignette 0.3 --depth");
  ASSERT_EQ(r.code, 0) << r.output;
  const Dataset d = OpenDataset(dir / "seq");
  EXPECT_EQ(d.format, "folder");
  EXPECT_EQ(d.size(), 5u);
  EXPECT_EQ(d.ground_truth.size(), 5u);
  ASSERT_TRUE(d.photometric.has_value());
  EXPECT_TRUE(d.photometric->has_vignette());
  EXPECT_TRUE(fs::exists(dir / "seq" / "depth" / "000004.tiff"));
  const Result info = RunDsm("info " + (dir / "seq").string());
  EXPECT_EQ(info.code, 0);
  EXPECT_TRUE(Contains(info.output, "frames:       5"));
  // Through a lens: camera.yaml gives it, the scene's focal length with the model's distortion.
  ASSERT_EQ(RunDsm("synth --scene shake --model fov --frames 2 --width 160 --height 120 --out " +
                   (dir / "fov").string()).code, 0);
  const Dataset fov = OpenDataset(dir / "fov");
  EXPECT_EQ(fov.camera.model, CameraModel::kFov);
  EXPECT_DOUBLE_EQ(fov.camera.fx, 0.6 * 160);
  EXPECT_EQ(fov.camera.distortion, synth::TypicalDistortion(CameraModel::kFov));
  const Result unknown = RunDsm("synth --scene shake --model fisheye2 --out " + (dir / "x").string());
  EXPECT_EQ(unknown.code, 2);
  EXPECT_TRUE(Contains(unknown.output, "--model")) << unknown.output;
}

// dsm synth --board renders views of a checkerboard and of a ChArUco board whose camera.yaml is the
// truth; dsm calibrate finds that camera back from the images and writes the camera.yaml dsm run
// reads, and the JSON contract (rms_px, views_used, intrinsics, distortion). Every model:
// calibration/calibrate_test.
TEST(Cli, CalibrateFindsTheCameraSynthRenderedTheBoardWith) {
  const std::vector<std::pair<std::string, int>> boards = {{"checkerboard:9x6:0.04", 9 * 6},
                                                           {"charuco:8x6:0.04:0.03:DICT_4X4_50", 7 * 5}};
  for (const auto& [spec, corners] : boards) {
    const fs::path dir = ScratchDir("cli_calibrate_" + spec.substr(0, 7));
    const std::string board = " --board " + spec;
    ASSERT_EQ(RunDsm("synth --model pinhole --views 8 --out " + (dir / "boards").string() + board).code, 0);
    const Result r = RunDsm("calibrate " + (dir / "boards").string() + board + " --model pinhole --out " +
                            (dir / "camera.yaml").string() + " --json " + (dir / "calib.json").string());
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(Contains(r.output, "reprojection RMS")) << r.output;
    const CameraYaml truth = ReadCameraYaml(dir / "boards" / "camera.yaml");
    const CameraYaml found = ReadCameraYaml(dir / "camera.yaml");
    EXPECT_EQ(found.camera.model, CameraModel::kPinhole);
    EXPECT_NEAR(found.camera.fx, truth.camera.fx, 0.003 * truth.camera.fx) << spec;
    EXPECT_NEAR(found.camera.cx, truth.camera.cx, 1.0) << spec;
    std::ifstream in(dir / "calib.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_LT(j["rms_px"].get<double>(), 0.2) << spec;
    EXPECT_GE(j["views_used"].get<int>(), 6);
    ASSERT_EQ(j["intrinsics"].size(), 4u);
    EXPECT_NEAR(j["intrinsics"][1].get<double>(), truth.camera.fy, 0.003 * truth.camera.fy) << spec;
    EXPECT_TRUE(j["distortion"].empty());
    // A checkerboard's view sees the whole board; a ChArUco board's may leave part of it out.
    for (const nlohmann::json& view : j["views"]) {
      const int seen = view["corners"].get<int>();
      if (spec.rfind("checkerboard", 0) == 0) {
        EXPECT_EQ(seen, corners) << spec;
      }
      EXPECT_LE(seen, corners) << spec;
      EXPECT_GE(seen, 8) << spec;
      if (view["used"].get<bool>()) {
        EXPECT_GE(view["corners_dropped"].get<int>(), 0) << spec;
      }
    }
  }
  const fs::path dir = ScratchDir("cli_calibrate_checker");
  const Result wrong = RunDsm("calibrate " + (dir / "boards").string() + " --board checkerboard:9x6");
  EXPECT_EQ(wrong.code, 2);
  EXPECT_TRUE(Contains(wrong.output, "checkerboard:COLSxROWS:SQUARE_M")) << wrong.output;
  const Result no_dict = RunDsm("calibrate " + (dir / "boards").string() + " --board charuco:8x6:0.04:0.03:DICT_4X4");
  EXPECT_EQ(no_dict.code, 2);
  EXPECT_TRUE(Contains(no_dict.output, "no ArUco dictionary 'DICT_4X4'")) << no_dict.output;
  const Result neither = RunDsm("synth --out " + (dir / "x").string());
  EXPECT_EQ(neither.code, 2);
  EXPECT_TRUE(Contains(neither.output, "--scene or --board")) << neither.output;
  const Result no_board = RunDsm("calibrate " + (dir / "boards").string());
  EXPECT_EQ(no_board.code, 2);
  EXPECT_TRUE(Contains(no_board.output, "--board is required (or --line-delay")) << no_board.output;
}

TEST(Cli, RunWritesTrajectoriesStatsAndEvaluation) {
  const fs::path dir = ScratchDir("cli_run");
  ASSERT_EQ(RunDsm("synth --scene shake --out " + (dir / "seq").string() + " --frames 60 --width 320 --height 240").code, 0);
  const Result r = RunDsm("run " + (dir / "seq").string() + " --out " + (dir / "out").string() + " --quiet --global-ba");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "frames tracked"));
  std::ifstream stats_in(dir / "out" / "stats.json");
  const nlohmann::json stats = nlohmann::json::parse(stats_in);
  for (const char* key : {"frames", "frames_tracked", "keyframes", "map_points", "initialized_at_frame", "wall_s",
                          "points_created", "reobservations", "covisible_keyframes_selected",
                          "points_created_per_keyframe", "per_keyframe", "frames_lost", "lost_episodes",
                          "relocalisations", "maps"})
    EXPECT_TRUE(stats.contains(key)) << key;
  EXPECT_EQ(stats["mode"], "dsm");  // The default.
  ASSERT_EQ(stats["maps"].size(), 1u);  // One map, in the output folder itself.
  EXPECT_EQ(stats["maps"][0]["dir"], ".");
  EXPECT_EQ(stats["maps"][0]["keyframes"], stats["keyframes"]);
  EXPECT_EQ(stats["points_created_per_keyframe"].size(), stats["keyframes"].get<size_t>());
  int created = 0;
  for (const auto& n : stats["points_created_per_keyframe"]) created += n.get<int>();
  EXPECT_EQ(created, stats["points_created"].get<int>());
  EXPECT_GE(stats["points_created"].get<int>(), stats["map_points"].get<int>());
  for (const char* part : {"tracking", "mapping"})
    for (const char* key : {"median", "p90", "mean"}) EXPECT_TRUE(stats["timing_ms"][part].contains(key)) << part << key;
  EXPECT_EQ(stats["frames"], 60);
  std::ifstream eval_in(dir / "out" / "eval.json");
  const nlohmann::json eval = nlohmann::json::parse(eval_in);
  EXPECT_TRUE(eval["keyframes"]["ape"].contains("rmse"));
  EXPECT_TRUE(eval["frames"]["ape"].contains("rmse"));
  EXPECT_TRUE(eval["keyframes_before_global_ba"]["ape"].contains("rmse"));
  EXPECT_GT(stats["timing_ms"]["global_ba"].get<double>(), 0.0);
  // Speed against the recording: 60 frames at the synthetic 20 Hz span 3 s.
  EXPECT_NEAR(stats["recording_s"].get<double>(), 3.0, 1e-6);
  EXPECT_NEAR(stats["realtime_factor"].get<double>() * stats["processing_s"].get<double>(), 3.0, 1e-6);
  EXPECT_NEAR(stats["frames_per_second"].get<double>() * stats["processing_s"].get<double>(), 60.0, 1e-6);
  EXPECT_LE(stats["processing_s"].get<double>(), stats["wall_s"].get<double>());
  EXPECT_TRUE(Contains(r.output, "x real time"));
  // Trajectories: TUM rows with nanosecond timestamps.
  const Trajectory frames = ReadTrajectory(dir / "out" / "frames.tum", TrajectoryFormat::kTum);
  EXPECT_EQ(static_cast<int>(frames.size()), stats["frames_tracked"].get<int>());
  EXPECT_EQ(frames.stamps_ns.front() % 1000, 0);  // the synthetic stamps are whole microseconds
}

// Progress: when stdout is not a terminal, plain lines at --progress-interval; none with --quiet.
TEST(Cli, RunPrintsProgressLinesUnlessQuiet) {
  const fs::path dir = ScratchDir("cli_progress");
  ASSERT_EQ(RunDsm("synth --scene shake --out " + (dir / "seq").string() + " --frames 30 --width 160 --height 120").code, 0);
  const std::string run = "run " + (dir / "seq").string() + " --sequential --out " + (dir / "out").string();
  const Result r = RunDsm(run + " --progress-interval 0");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "frame 1/30 (3%)")) << r.output;
  EXPECT_TRUE(Contains(r.output, "frame 30/30 (100%)")) << r.output;
  EXPECT_TRUE(Contains(r.output, " keyframes ")) << r.output;
  EXPECT_TRUE(Contains(r.output, "tracking")) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\r'), 0);  // No redrawing outside a terminal.
  const Result quiet = RunDsm(run + " --quiet");
  ASSERT_EQ(quiet.code, 0) << quiet.output;
  EXPECT_FALSE(Contains(quiet.output, "frame 1/30")) << quiet.output;
  EXPECT_TRUE(Contains(quiet.output, "30/30 frames tracked")) << quiet.output;
  // Three frames: the map never starts, and every output is still written.
  const Result short_run = RunDsm(run + " --end 3 --quiet");
  ASSERT_EQ(short_run.code, 0) << short_run.output;
  for (const char* file : {"keyframes.tum", "frames.tum", "stats.json", "map.ply", "keyframes.ply", "report.html"})
    EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;
  const Result bad = RunDsm(run + " --progress-interval -1");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(Contains(bad.output, "--progress-interval")) << bad.output;
  const Result bad_wait = RunDsm(run + " --latency-target-ms -5");
  EXPECT_EQ(bad_wait.code, 2);
  EXPECT_TRUE(Contains(bad_wait.output, "--latency-target-ms")) << bad_wait.output;
}

// `--debug DIR` on a rendered sequence with depth: a row per keyframe, a picture and a point table
// per keyframe, and on a well-tracked sequence neither the motion's scale nor the points' depths
// drift from the scale the map started with.
// Renders `shake` at 320x240 (`synth_args`: its frames and extras) in dir/seq and runs it into
// dir/run with `--debug dir/debug`; the rendering's result when it fails, else the run's.
Result RunShakeWithDebug(const fs::path& dir, const std::string& synth_args) {
  const Result synth = RunDsm("synth --scene shake --out " + (dir / "seq").string() + " --width 320 --height 240 " + synth_args);
  if (synth.code != 0) return synth;
  return RunDsm("run " + (dir / "seq").string() + " --out " + (dir / "run").string() + " --quiet --debug " +
                (dir / "debug").string());
}

TEST(Cli, RunDebugWritesPerKeyframeDiagnostics) {
  const fs::path dir = ScratchDir("cli_debug");
  const Result r = RunShakeWithDebug(dir, "--frames 50 --depth");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream stats_file(dir / "run" / "stats.json");
  const int keyframes = nlohmann::json::parse(stats_file)["keyframes"];
  ASSERT_GE(keyframes, 3);
  std::ifstream table(dir / "debug" / "keyframes.csv");
  std::string header, line;
  std::getline(table, header);
  const auto column = [&](const std::string& name) {
    std::stringstream h(header);
    std::string field;
    for (int i = 0; std::getline(h, field, ','); ++i)
      if (field == name) return i;
    return -1;
  };
  const int drift = column("scale_drift"), depth_drift = column("depth_scale_drift"), points = column("points");
  ASSERT_GE(drift, 0);
  ASSERT_GE(depth_drift, 0);
  int rows = 0;
  while (std::getline(table, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), static_cast<size_t>(std::count(header.begin(), header.end(), ',') + 1)) << line;
    EXPECT_EQ(std::stoi(f[0]), rows);
    EXPECT_GT(std::stoi(f[points]), 50) << line;
    if (rows >= 2) {
      EXPECT_NEAR(std::stod(f[drift]), 1.0, 0.1) << line;
      EXPECT_NEAR(std::stod(f[depth_drift]), 1.0, 0.05) << line;
    }
    char name[64];
    std::snprintf(name, sizeof(name), "kf_%05d.png", rows);
    EXPECT_TRUE(fs::exists(dir / "debug" / name)) << name;
    std::snprintf(name, sizeof(name), "kf_%05d_points.csv", rows);
    EXPECT_TRUE(fs::exists(dir / "debug" / name)) << name;
    ++rows;
  }
  EXPECT_EQ(rows, keyframes);
  EXPECT_NE(RunDsm("run " + (dir / "seq").string() + " --out " + (dir / "run2").string() + " --debug /proc/no_such").code, 0);
}

// `--debug DIR` writes a row per frame read: black frames are lost with the reason, a corrupt file
// is skipped with its error, and the row count and keyframes agree with stats.json.
TEST(Cli, RunDebugWritesPerFrameStatus) {
  const fs::path dir = ScratchDir("cli_debug_frames");
  const Result r = RunShakeWithDebug(dir, "--frames 60 --defects black:40-42,corrupt:50");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream stats_file(dir / "run" / "stats.json");
  const nlohmann::json stats = nlohmann::json::parse(stats_file);
  std::ifstream table(dir / "debug" / "frames.csv");
  std::string line;
  std::getline(table, line);
  EXPECT_EQ(line, "frame,map,status,keyframe,relocalised,tracking_ms,reason");
  int rows = 0, keyframes = 0, lost = 0;
  while (std::getline(table, line)) {
    std::stringstream ss(line);
    std::vector<std::string> f;
    for (std::string x; f.size() < 6 && std::getline(ss, x, ',');) f.push_back(x);
    std::string reason;
    std::getline(ss, reason);
    ASSERT_EQ(f.size(), 6u) << line;
    EXPECT_EQ(std::stoi(f[0]), rows) << line;
    EXPECT_EQ(f[1], "0") << line;
    keyframes += f[3] == "1";
    lost += f[2] == "lost";
    if (rows >= 40 && rows <= 42) {
      EXPECT_EQ(f[2], "lost") << line;
      EXPECT_NE(reason.find("texture"), std::string::npos) << line;
    }
    if (rows == 50) {
      EXPECT_EQ(f[2], "skipped") << line;
      EXPECT_NE(reason.find("000050.png"), std::string::npos) << line;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 60);
  EXPECT_EQ(keyframes + 1, stats["keyframes"].get<int>());  // The start's reference frame is not marked.
  EXPECT_EQ(lost, stats["frames_lost"].get<int>());
}

// `dsm run --print-config` writes a valid options file: read back with --config, it prints the
// same; with a changed key the change shows, and the file runs.
TEST(Cli, PrintConfigRoundTrips) {
  const fs::path dir = ScratchDir("cli_print_config");
  const Result defaults = RunDsm("run --print-config");
  ASSERT_EQ(defaults.code, 0) << defaults.output;
  EXPECT_TRUE(Contains(defaults.output, "\nwindow:\n  temporal_keyframes: 4  # ")) << defaults.output;
  WriteText(dir / "all.yaml", defaults.output);
  const Result again = RunDsm("run --print-config --config " + (dir / "all.yaml").string());
  EXPECT_EQ(again.code, 0);
  EXPECT_EQ(again.output, defaults.output);
  const Result changed = RunDsm("run --print-config --nc 2 --config " + (dir / "all.yaml").string());
  EXPECT_TRUE(Contains(changed.output, "\n  covisible_keyframes: 2  # ")) << changed.output;
  ASSERT_EQ(RunDsm("synth --scene shake --frames 30 --width 160 --height 120 --out " + (dir / "seq").string()).code, 0);
  const Result run = RunDsm("run " + (dir / "seq").string() + " --sequential --quiet --no-report --no-map --config " +
                            (dir / "all.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(run.code, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "keyframes.tum"));
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// Damaged files cost their frame, with one warning naming the file (not the codec's own output);
// black and noise frames go through the system without numeric failures.
TEST(Cli, BadFramesCostTheirFrameNotTheRun) {
  const fs::path dir = ScratchDir("cli_bad_frames");
  ASSERT_EQ(RunDsm("synth --scene shake --out " + (dir / "seq").string() +
                   " --frames 40 --width 320 --height 240 --defects corrupt:12,truncated:13,empty:14,black:20-22,noise:25")
                .code,
            0);
  const Result r = RunDsm("run " + (dir / "seq").string() + " --sequential --quiet --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "000012.png: cannot decode the image (corrupt PNG: chunk IDAT")) << r.output;
  EXPECT_TRUE(Contains(r.output, "000013.png: cannot decode the image (truncated PNG")) << r.output;
  EXPECT_TRUE(Contains(r.output, "000014.png: cannot decode the image (empty file); frame 14 skipped")) << r.output;
  EXPECT_FALSE(Contains(r.output, "libpng")) << r.output;
  const nlohmann::json stats = ReadJson(dir / "out" / "stats.json");
  EXPECT_EQ(stats["frames_skipped"], 3);
  EXPECT_EQ(stats["skipped_frames"], nlohmann::json::array({12, 13, 14}));
  EXPECT_EQ(stats["frames"], 37);
  EXPECT_EQ(stats["interrupted"], false);
  EXPECT_GE(ReadTrajectory(dir / "out" / "frames.tum", TrajectoryFormat::kTum).size(), 12u);
}

// `dsm damage`: a EuRoC copy that links the good images, writes the spoiled ones (a black frame is
// all 0), damages the file of a corrupt one, leaves cut frames out of the list and keeps the ground
// truth; `dsm info` reads it.
TEST(Cli, DamageWritesAEurocCopyWithTheDefects) {
  const fs::path dir = ScratchDir("cli_damage");
  const fs::path src = SharedDataDir() / "euroc_mh01_shake";
  const Result r = RunDsm("damage " + src.string() + " --out " + (dir / "d").string() +
                          " --defects black:3-4,corrupt:6,cut:10-19");
  ASSERT_EQ(r.code, 0) << r.output;
  const Dataset clean = OpenDataset(src);
  const Dataset damaged = OpenDataset(dir / "d");
  ASSERT_EQ(damaged.size(), clean.size() - 10);
  EXPECT_EQ(damaged.frames[9].t_ns, clean.frames[9].t_ns);
  EXPECT_EQ(damaged.frames[10].t_ns, clean.frames[20].t_ns);
  EXPECT_EQ(damaged.ground_truth.size(), clean.ground_truth.size());
  const fs::path data = dir / "d" / "mav0" / "cam0" / "data";
  EXPECT_TRUE(fs::is_symlink(data / clean.frames[2].image));
  EXPECT_FALSE(fs::is_symlink(data / clean.frames[3].image));
  const Image<uint8_t> black = damaged.LoadImage(3);
  EXPECT_EQ(*std::max_element(black.data(), black.data() + black.width() * black.height()), 0);
  EXPECT_NE(fs::file_size(data / clean.frames[6].image), 0u);
  EXPECT_THROW(damaged.LoadImage(6), InputError);
  EXPECT_FALSE(fs::exists(data / clean.frames[15].image));
  const Result info = RunDsm("info " + (dir / "d").string());
  EXPECT_EQ(info.code, 0) << info.output;
  EXPECT_TRUE(Contains(info.output, "frames:       330")) << info.output;
}

// A live camera that cannot be read is a message naming it, exit 2 (streams: tests/camera_test).
TEST(Cli, ACameraThatDoesNotOpenIsAMessage) {
  const fs::path dir = ScratchDir("cli_camera");
  ASSERT_EQ(RunDsm("synth --scene loop --frames 2 --width 320 --height 240 --out " + (dir / "seq").string()).code, 0);
  const std::string calib = " --calib " + (dir / "seq" / "camera.yaml").string() + " --out " + (dir / "out").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--camera /dev/video99" + calib, "/dev/video99: the camera does not open"},
      {"--camera 98" + calib, "no V4L2 device /dev/video98"},
      {"--camera tcp://127.0.0.1:1" + calib, "tcp://127.0.0.1:1: the stream does not open"},
      // Nobody connects to a listening stream: the stall timeout bounds the wait.
      {"--camera \"tcp://127.0.0.1:" + std::to_string(21000 + getpid() % 20000) + "?listen=1\" --stall-timeout 1" + calib,
       "does not open within 1 s"},
      {"--camera /dev/video0 --out " + (dir / "out").string(), "--camera needs the camera's calibration (--calib"},
      {(dir / "seq").string() + " --camera /dev/video0" + calib, "or --camera, one of them"},
      {"--camera /dev/video0 --sequential" + calib, "--camera runs in the realtime pace"},
      {"--camera /dev/video0 --stall-timeout 0" + calib, "--stall-timeout must be within 0 and 3600 seconds"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = RunDsm("run " + args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_TRUE(Contains(r.output, message)) << args << "\n" << r.output;
  }
}

// SIGTERM (and SIGINT) finish the current frame and write what the run has: exit 128 + signal.
TEST(Cli, SigtermWritesTheRunSoFar) {
  const fs::path dir = ScratchDir("cli_sigterm");
  ASSERT_EQ(RunDsm("synth --scene shake --out " + (dir / "seq").string() + " --frames 200 --width 320 --height 240").code, 0);
  // Realtime pace: 200 frames at 20 Hz take 10 s, the signal comes after 4.
  const std::string command = "sh -c '" + std::string(DSM_CLI_PATH) + " run " + (dir / "seq").string() +
                              " --realtime --quiet --out " + (dir / "out").string() +
                              " > " + (dir / "log.txt").string() + " 2>&1 & p=$!; sleep 4; kill -TERM $p; wait $p; echo $?'";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char code[32] = {0};
  ASSERT_NE(fgets(code, sizeof(code), pipe), nullptr);
  pclose(pipe);
  EXPECT_EQ(std::atoi(code), 143);
  const nlohmann::json stats = ReadJson(dir / "out" / "stats.json");
  EXPECT_EQ(stats["interrupted"], true);
  EXPECT_LT(stats["frames"].get<int>(), 200);
  EXPECT_GT(stats["frames"].get<int>(), 10);
  EXPECT_TRUE(fs::exists(dir / "out" / "keyframes.tum"));
  // The evaluation so far, once there is something to align (a slow build, e.g. with sanitizers,
  // may not have three keyframes after the first seconds).
  if (stats["keyframes"].get<int>() >= 3) {
    EXPECT_TRUE(fs::exists(dir / "out" / "eval.json"));
  }
}

}  // namespace
}  // namespace dsm

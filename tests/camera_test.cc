// SPDX-License-Identifier: MIT
// dsm run --camera as it is used: a rendered sequence streamed by ffmpeg over the loopback
// interface (H.264, lossless, at the sequence's rate) into `dsm run --camera URL`. The live run
// tracks nearly every frame, as accurately as the same frames run from files in the realtime pace;
// --record writes what was captured as a dataset that replays; a stream cut, stopped or
// interrupted half-way ends the run with every output written. And `dsm calibrate --line-delay`
// on a recording.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dsm/eval/metrics.h"
#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

using Result = testing::CommandResult;

// `command` run by sh (its own background jobs and `wait`s included).
Result Shell(const std::string& command) { return testing::RunCommand("sh -c '" + command + "'"); }

const std::string kDsm = DSM_CLI_PATH;

// A port of its own for each stream of each test process.
int Port(int k) { return 20000 + static_cast<int>(getpid() % 20000) + k; }

// ffmpeg sending the sequence's images at `rate` Hz, as a camera would, to a listening dsm.
std::string Stream(const fs::path& seq, int port, int rate = 20) {
  return "ffmpeg -hide_banner -loglevel error -re -framerate " + std::to_string(rate) + " -i " +
         (seq / "images" / "%06d.png").string() +
         " -c:v libx264 -preset ultrafast -tune zerolatency -qp 0 -pix_fmt yuv420p -f mpegts tcp://127.0.0.1:" +
         std::to_string(port);
}

std::string Listen(int port) { return "\"tcp://127.0.0.1:" + std::to_string(port) + "?listen=1\""; }

// dsm run --camera in the background, the stream into it a second later, then `then` (with $d the
// dsm process, $f ffmpeg's); prints dsm's exit code last.
Result LiveRun(const fs::path& seq, const fs::path& out, int port, const std::string& options,
               const std::string& then = "") {
  return Shell(kDsm + " run --camera " + Listen(port) + " --calib " + (seq / "camera.yaml").string() + " --out " +
               out.string() + " --quiet " + options + " > " + (out.string() + ".log") + " 2>&1 & d=$!; sleep 1; " +
               Stream(seq, port) + " & f=$!; " + then + " wait $d; echo exit $?; kill -9 $f 2>/dev/null; wait");
}

int ExitOf(const Result& r) {
  const size_t at = r.output.rfind("exit ");
  return at == std::string::npos ? -1 : std::atoi(r.output.c_str() + at + 5);
}

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::string Log(const fs::path& out) {
  std::ifstream in(out.string() + ".log");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The live run's keyframe ATE (Sim(3)) against the sequence's truth: each capture time (the
// recording's times.txt) is the time of the sequence's frame with its index (TCP loses none).
double LiveKeyframeAte(const fs::path& out, const fs::path& recording, const Dataset& seq) {
  const Dataset rec = OpenDataset(recording);
  std::map<int64_t, int64_t> source_time;
  for (size_t i = 0; i < rec.frames.size(); ++i) source_time[rec.frames[i].t_ns] = seq.frames.at(i).t_ns;
  Trajectory keyframes = ReadTrajectory(out / "keyframes.tum", TrajectoryFormat::kTum);
  for (int64_t& t : keyframes.stamps_ns) t = source_time.at(t);
  EvalOptions options;
  options.align = Alignment::kSim3;
  return Evaluate(seq.ground_truth, keyframes, options).ape.rmse;
}

void ExpectOutputs(const fs::path& out) {
  for (const char* file : {"keyframes.tum", "frames.tum", "stats.json", "map.ply", "report.html"})
    EXPECT_TRUE(fs::exists(out / file)) << out / file;
}

TEST(Camera, AStreamTracksLikeItsFilesAndItsRecordingReplays) {
  const fs::path dir = testing::ScratchDir("camera_stream");
  const fs::path seq = dir / "seq";
  ASSERT_EQ(Shell(kDsm + " synth --scene loop --seed 1 --frames 300 --out " + seq.string()).code, 0);
  const Result live = LiveRun(seq, dir / "live", Port(0), "--record " + (dir / "rec").string());
  ASSERT_EQ(ExitOf(live), 0) << live.output << Log(dir / "live");
  const nlohmann::json stats = ReadJson(dir / "live" / "stats.json");
  EXPECT_EQ(stats["live"]["ended"], "ended");
  EXPECT_EQ(stats["pace"], "realtime");
  ASSERT_EQ(stats["live"]["frames_captured"].get<int>(), 300);
  const int tracked = stats["frames_tracked"].get<int>();
  // Frames the tracker could not take were dropped: the rest are what it saw.
  EXPECT_EQ(stats["frames"].get<int>() + stats["frames_dropped"].get<int>(), 300);
  EXPECT_GE(tracked, 285) << Log(dir / "live");
  ExpectOutputs(dir / "live");

  // The same frames from files, released at their times.
  const Result files = Shell(kDsm + " run " + seq.string() + " --realtime --quiet --out " + (dir / "files").string());
  ASSERT_EQ(files.code, 0) << files.output;
  const double files_ate = ReadJson(dir / "files" / "eval.json")["keyframes"]["ape"]["rmse"].get<double>();
  const Dataset truth = OpenDataset(seq);
  const double live_ate = LiveKeyframeAte(dir / "live", dir / "rec", truth);
  std::printf("live: %d/300 tracked, keyframe ATE %.3f mm; from files (realtime): %.3f mm\n", tracked,
              1e3 * live_ate, 1e3 * files_ate);
  EXPECT_LT(live_ate, 1.5 * files_ate);

  // The recording: every frame captured, at its capture time; the live run's frames among them.
  const Dataset rec = OpenDataset(dir / "rec");
  ASSERT_EQ(rec.size(), 300u);
  EXPECT_EQ(rec.camera.fx, truth.camera.fx);
  const Trajectory frames = ReadTrajectory(dir / "live" / "frames.tum", TrajectoryFormat::kTum);
  std::map<int64_t, bool> recorded;
  for (const FrameRecord& f : rec.frames) recorded[f.t_ns] = true;
  for (int64_t t : frames.stamps_ns) EXPECT_TRUE(recorded.count(t)) << t;
  const Result replay =
      Shell(kDsm + " run " + (dir / "rec").string() + " --sequential --quiet --out " + (dir / "replay").string());
  ASSERT_EQ(replay.code, 0) << replay.output;
  EXPECT_GE(ReadJson(dir / "replay" / "stats.json")["frames_tracked"].get<int>(), 285) << replay.output;
}

TEST(Camera, AStreamCutStoppedOrInterruptedEndsTheRunWithEveryOutput) {
  const fs::path dir = testing::ScratchDir("camera_cut");
  const fs::path seq = dir / "seq";
  ASSERT_EQ(Shell(kDsm + " synth --scene loop --seed 2 --frames 300 --width 320 --height 240 --out " + seq.string()).code, 0);
  // The sender killed half-way: the stream ends there.
  const Result cut = LiveRun(seq, dir / "cut", Port(1), "--save-map " + (dir / "cut.dsm").string(), "sleep 7; kill -9 $f;");
  EXPECT_EQ(ExitOf(cut), 0) << cut.output << Log(dir / "cut");
  ExpectOutputs(dir / "cut");
  EXPECT_TRUE(fs::exists(dir / "cut.dsm"));
  nlohmann::json stats = ReadJson(dir / "cut" / "stats.json");
  EXPECT_EQ(stats["live"]["ended"], "ended");
  EXPECT_GT(stats["live"]["frames_captured"].get<int>(), 60);
  EXPECT_LT(stats["live"]["frames_captured"].get<int>(), 250);
  // The sender stopped (SIGSTOP): no frame for --stall-timeout ends the run.
  const Result stalled = LiveRun(seq, dir / "stalled", Port(2), "--stall-timeout 2", "sleep 5; kill -STOP $f;");
  EXPECT_EQ(ExitOf(stalled), 0) << stalled.output << Log(dir / "stalled");
  ExpectOutputs(dir / "stalled");
  stats = ReadJson(dir / "stalled" / "stats.json");
  EXPECT_EQ(stats["live"]["ended"], "stalled");
  EXPECT_NE(stats["live"]["message"].get<std::string>().find("no frame for 2 s"), std::string::npos);
  // Ctrl-C: exit 130, every output and the map file.
  const Result interrupted =
      LiveRun(seq, dir / "int", Port(3), "--save-map " + (dir / "int.dsm").string(), "sleep 6; kill -INT $d;");
  EXPECT_EQ(ExitOf(interrupted), 130) << interrupted.output << Log(dir / "int");
  ExpectOutputs(dir / "int");
  EXPECT_TRUE(fs::exists(dir / "int.dsm"));
  stats = ReadJson(dir / "int" / "stats.json");
  EXPECT_EQ(stats["live"]["ended"], "interrupted");
  EXPECT_EQ(stats["interrupted"], true);
}

TEST(Camera, AFrameSizeTheCalibrationDoesNotFitIsAMessageWithTheOutputsSoFar) {
  const fs::path dir = testing::ScratchDir("camera_size");
  const fs::path seq = dir / "seq";
  ASSERT_EQ(Shell(kDsm + " synth --scene loop --frames 100 --width 320 --height 240 --out " + seq.string()).code, 0);
  // A calibration of another camera (640x480).
  ASSERT_EQ(Shell(kDsm + " synth --scene loop --frames 2 --out " + (dir / "other").string()).code, 0);
  const int port = Port(4);
  const Result r = Shell(kDsm + " run --camera " + Listen(port) + " --calib " + (dir / "other" / "camera.yaml").string() +
                         " --out " + (dir / "out").string() + " --quiet & d=$!; sleep 1; " + Stream(seq, port) +
                         " 2>/dev/null; wait $d; echo exit $?");
  EXPECT_EQ(ExitOf(r), 2) << r.output;
  EXPECT_NE(r.output.find("frames are 320x240 but the calibration"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "stats.json"));
}

// dsm calibrate --line-delay on a recording of a scene: a global shutter's delay comes out 0 and
// is written to the camera.yaml (rolling shutters: run/rolling_shutter in run_synthetic_test).
TEST(Camera, CalibrateEstimatesTheLineDelayOfARecording) {
  const fs::path dir = testing::ScratchDir("camera_line_delay");
  ASSERT_EQ(Shell(kDsm + " synth --scene loop --frames 60 --width 320 --height 240 --out " + (dir / "seq").string()).code, 0);
  const Result r = Shell(kDsm + " calibrate " + (dir / "seq").string() + " --line-delay --out " +
                         (dir / "camera.yaml").string() + " --json " + (dir / "delay.json").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("line delay: 0.0 us per row"), std::string::npos) << r.output;
  EXPECT_EQ(ReadCameraYaml(dir / "camera.yaml").line_delay_us, 0.0);
  std::ifstream json(dir / "delay.json");
  EXPECT_EQ(nlohmann::json::parse(json)["trials"].size(), 17u);  // 0 .. 16/16 of a 320x240 frame's interval.
  const Result both = Shell(kDsm + " calibrate " + (dir / "seq").string() + " --line-delay --board checkerboard:9x6:0.04");
  EXPECT_EQ(both.code, 2);
  EXPECT_NE(both.output.find("exclude each other"), std::string::npos) << both.output;
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// End to end on every rendered scene (DSM-SW): initialised within 30 frames, >= 99% of the frames
// tracked, keyframe RMS ATE (Sim(3)) <= 0.5% of the camera path; and two runs give identical output.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "dsm/run/run.h"
#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

fs::path Render(const std::string& scene, int frames) {
  synth::SynthOptions options;
  options.scene = scene;
  options.frames = frames;
  const fs::path dir = testing::ScratchDir("run_" + scene + "_" + std::to_string(frames)) / "sequence";
  synth::WriteSequence(synth::MakeSequence(options), options, dir);
  return dir;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SyntheticRun : public ::testing::TestWithParam<std::string> {};

TEST_P(SyntheticRun, MeetsTheAccuracyTargets) {
  const fs::path dir = Render(GetParam(), 0);
  const Dataset dataset = OpenDataset(dir);
  RunOptions options;
  options.quiet = true;
  const RunSummary s = RunDataset(dataset, options, dir.parent_path() / "out");
  std::printf("%s: %s\n", GetParam().c_str(), s.line.c_str());
  const int frames = s.stats["frames"];
  EXPECT_LE(s.stats["initialized_at_frame"].get<int>(), 30);
  EXPECT_GE(s.stats["frames_tracked"].get<int>(), 0.99 * frames);
  ASSERT_TRUE(s.eval.has_value());
  const double path = dataset.ground_truth.PathLength();
  EXPECT_LE((*s.eval)["keyframes"]["ape"]["rmse"].get<double>(), 0.005 * path) << "path " << path << " m";
}

INSTANTIATE_TEST_SUITE_P(Scenes, SyntheticRun, ::testing::Values("loop", "shake", "forward", "rotation", "exposure"),
                         [](const ::testing::TestParamInfo<std::string>& param) { return param.param; });

TEST(Run, TwoRunsGiveIdenticalOutput) {
  const fs::path dir = Render("shake", 80);
  const Dataset dataset = OpenDataset(dir);
  RunOptions options;
  options.quiet = true;
  RunDataset(dataset, options, dir.parent_path() / "a");
  RunDataset(dataset, options, dir.parent_path() / "b");
  for (const char* file : {"keyframes.tum", "frames.tum", "eval.json"}) {
    const std::string a = ReadFile(dir.parent_path() / "a" / file), b = ReadFile(dir.parent_path() / "b" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, b) << file;
  }
}

TEST(Run, RejectsAnEmptyFrameRange) {
  const fs::path dir = Render("shake", 5);
  RunOptions options;
  options.start = 4;
  options.end = 2;
  EXPECT_THROW(RunDataset(OpenDataset(dir), options, dir.parent_path() / "out"), InputError);
}

}  // namespace
}  // namespace dsm

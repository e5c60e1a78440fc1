// SPDX-License-Identifier: MIT
// Loop closure end to end (mapping_loop.cc). `block` (a 98 m ring corridor walked 1.2 times, at
// 320 x 240): without loop closure the camera comes back with the drift of the lap and the
// second pass maps the place anew; with it, the place is recognised within 10 keyframes of the
// return, the loop is closed once, and the keyframe ATE falls to at most half. `twins` (a
// corridor whose second half is a copy of the first): the copy is recognised as the place seen
// before, but the loop is refused, since it would move the camera by half the path, and the map
// stays as without loop closure.
#include <gtest/gtest.h>

#include "dsm/run/run.h"
#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;

fs::path Render(const std::string& scene, int width, int height) {
  synth::SynthOptions options;
  options.scene = scene;
  options.width = width;
  options.height = height;
  const fs::path dir = testing::ScratchDir("loop_closure_" + scene) / "sequence";
  synth::WriteSequence(synth::MakeSequence(options), options, dir);
  return dir;
}

RunSummary RunSequential(const fs::path& dir, bool loop_closure) {
  RunOptions options;
  options.pace = Pace::kSequential;
  options.quiet = true;
  options.system.loop_closure.enabled = loop_closure;
  RunSummary s = RunDataset(OpenDataset(dir), options, dir.parent_path() / (loop_closure ? "closed" : "open"));
  std::printf("%s\n", s.line.c_str());
  return s;
}

double KeyframeAte(const RunSummary& s) { return (*s.eval)["keyframes"]["ape"]["rmse"].get<double>(); }

TEST(LoopClosure, TheBlockIsClosedSoonAfterTheReturnAndTheErrorFalls) {
  const fs::path dir = Render("block", 320, 240);
  const RunSummary open = RunSequential(dir, false);
  const RunSummary closed = RunSequential(dir, true);
  EXPECT_EQ(open.stats["loops_closed"].size(), 0u);
  ASSERT_EQ(closed.stats["loops_closed"].size(), 1u);
  const nlohmann::json& loop = closed.stats["loops_closed"][0];
  // The camera is back at its start after one lap: 98.3 m at 2 m/s, 20 frames a second.
  constexpr int kReturnFrame = 983;
  int keyframes_after_return = 0;
  for (const auto& k : closed.stats["per_keyframe"]) {
    const int frame = k["frame"];
    keyframes_after_return += frame > kReturnFrame && frame <= loop["frame"].get<int>();
  }
  EXPECT_GT(loop["frame"].get<int>(), kReturnFrame);
  EXPECT_LE(keyframes_after_return, 10);
  EXPECT_LT(loop["candidate_keyframe"].get<int>(), 20);  // A keyframe of the lap's start.
  EXPECT_LT(loop["translation_share"].get<double>(), 0.05);
  EXPECT_LE(KeyframeAte(closed), 0.5 * KeyframeAte(open));
}

TEST(LoopClosure, ATwinCorridorIsRecognisedButNotJoined) {
  const fs::path dir = Render("twins", 320, 240);
  const RunSummary closed = RunSequential(dir, true);
  EXPECT_GT(closed.stats["loops_detected"].get<int>(), 0);
  EXPECT_EQ(closed.stats["loops_closed"].size(), 0u);
  // The keyframe ATE of the 17 m walk stays that of a map without a wrong loop.
  EXPECT_LT(KeyframeAte(closed), 0.005);
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// End to end on the shared EuRoC frames, both modes: initialised within 20 frames, every later
// frame tracked, keyframe RMS ATE (Sim(3)) <= 12 mm.
#include <gtest/gtest.h>

#include "dsm/run/run.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

TEST(EurocRun, BothModesMeetTheAccuracyTarget) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / "euroc_mh01_shake");
  for (const MapMode mode : {MapMode::kSlidingWindow, MapMode::kFull}) {
    RunOptions options;
    options.quiet = true;
    options.system.mode = mode;
    const RunSummary s = RunDataset(dataset, options, testing::ScratchDir("euroc_run"));
    std::printf("euroc %s: %s (PBA %.0f ms/KF)\n", mode == MapMode::kFull ? "dsm" : "sw", s.line.c_str(),
                s.stats["timing_ms"]["pba"]["mean"].get<double>());
    const int init = s.stats["initialized_at_frame"];
    EXPECT_LE(init, 20);
    EXPECT_GE(s.stats["frames_tracked"].get<int>(), s.stats["frames"].get<int>() - init);
    ASSERT_TRUE(s.eval.has_value());
    EXPECT_LE((*s.eval)["keyframes"]["ape"]["rmse"].get<double>(), 0.012);
  }
}

}  // namespace
}  // namespace dsm

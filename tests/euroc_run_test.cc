// SPDX-License-Identifier: MIT
// End to end on the shared EuRoC frames (DSM-SW): initialised within 20 frames, every later frame
// tracked, keyframe RMS ATE (Sim(3)) <= 12 mm.
#include <gtest/gtest.h>

#include "dsm/run/run.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

TEST(EurocRun, SlidingWindowAccuracy) {
  const Dataset dataset = OpenDataset(testing::SharedDataDir() / "euroc_mh01_shake");
  RunOptions options;
  options.quiet = true;
  const RunSummary s = RunDataset(dataset, options, testing::ScratchDir("euroc_run"));
  std::printf("euroc: %s\n", s.line.c_str());
  const int init = s.stats["initialized_at_frame"];
  EXPECT_LE(init, 20);
  EXPECT_GE(s.stats["frames_tracked"].get<int>(), s.stats["frames"].get<int>() - init);
  ASSERT_TRUE(s.eval.has_value());
  EXPECT_LE((*s.eval)["keyframes"]["ape"]["rmse"].get<double>(), 0.012);
}

}  // namespace
}  // namespace dsm

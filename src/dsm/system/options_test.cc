// SPDX-License-Identifier: MIT
#include "dsm/system/options.h"

#include <string>

#include <gtest/gtest.h>

#include "dsm/testing/input_error.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

// The map sizes (1..200 keyframes) at which the young map is bundle-adjusted.
std::vector<int> DueKeyframes(const SystemOptions& options) {
  std::vector<int> due;
  for (int n = 1; n <= 200; ++n)
    if (options.YoungMapBaDue(n)) due.push_back(n);
  return due;
}

// The young map is bundle-adjusted whole at first, 2 first, 4 first, ... keyframes up to the last.
TEST(SystemOptions, YoungMapBundleAdjustmentsDoubleUpToTheLast) {
  SystemOptions options;
  options.young_map_ba_first = 5;
  options.young_map_ba_last = 40;
  EXPECT_EQ(DueKeyframes(options), (std::vector<int>{5, 10, 20, 40}));
  options.young_map_ba_last = 39;
  EXPECT_FALSE(options.YoungMapBaDue(40));
  EXPECT_TRUE(options.YoungMapBaDue(20));
  options.young_map_ba_last = 0;  // None.
  EXPECT_TRUE(DueKeyframes(options).empty());
  // DSM-SW keeps no map beyond its window.
  options.young_map_ba_last = 40;
  options.mode = MapMode::kSlidingWindow;
  EXPECT_FALSE(options.YoungMapBaDue(5));
}

TEST(SystemOptions, RejectsAYoungMapScheduleThatNeverGrows) {
  SystemOptions options;
  options.young_map_ba_first = 1;
  EXPECT_THROW(options.Validate(), InputError);
  options.young_map_ba_first = 5;
  options.young_map_ba_last = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.young_map_ba_last = 0;
  EXPECT_NO_THROW(options.Validate());
}

TEST(SystemOptions, RejectsANegativeNoiseLevelForTheTextureLossTest) {
  SystemOptions options;
  options.texture_loss_min_noise = -1.0;
  EXPECT_NE(testing::MessageOf([&] { options.Validate(); }).find("system.texture_loss_min_noise"), std::string::npos);
  options.texture_loss_min_noise = 0.0;  // Never.
  EXPECT_NO_THROW(options.Validate());
}

TEST(SystemOptions, RejectsALoopAdjustmentWithoutABound) {
  SystemOptions options;
  options.loop_ba_min_gap = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.loop_ba_min_gap = 20;
  EXPECT_NO_THROW(options.Validate());
  options.loop_ba_max_keyframes = 1;
  EXPECT_THROW(options.Validate(), InputError);
  options.loop_ba_max_keyframes = 120;
  options.loop_ba_max_iterations = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.loop_ba_max_iterations = 0;
  options.loop_ba_after_relocalisation = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.loop_ba_after_relocalisation = 0;
  EXPECT_NO_THROW(options.Validate());
}

TEST(SystemOptions, RejectsASeamAdjustmentOutOfRange) {
  SystemOptions options;
  options.seam_ba_count = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.seam_ba_count = 0;  // Never.
  EXPECT_NO_THROW(options.Validate());
  options.seam_ba_step = 0;
  EXPECT_THROW(options.Validate(), InputError);
  options.seam_ba_step = 1;
  options.seam_ba_before = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.seam_ba_before = 0;
  EXPECT_NO_THROW(options.Validate());
  options.rejoin_min_outliers = -1;
  EXPECT_THROW(options.Validate(), InputError);
  options.rejoin_min_outliers = 0;  // Never.
  EXPECT_NO_THROW(options.Validate());
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/place/place_groups.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(ConsistentGroups, APlaceFoundThreeKeyframesInARowIsDetectedOnce) {
  std::vector<PlaceGroup> groups;
  int found = 0;
  // The returning camera's keyframes see keyframes 20-23 one after another (their best moves on).
  EXPECT_TRUE(ConsistentGroups({{0.5, 20}, {0.3, 21}}, 3, &groups, &found).empty());
  EXPECT_TRUE(ConsistentGroups({{0.6, 22}}, 3, &groups, &found).empty());
  EXPECT_EQ(found, 0);
  EXPECT_EQ(ConsistentGroups({{0.4, 21}, {0.7, 23}}, 3, &groups, &found), (std::vector<int>{21, 23}));
  EXPECT_EQ(found, 2);  // Both overlapping groups reached the count now ...
  ConsistentGroups({{0.7, 24}}, 3, &groups, &found);
  EXPECT_EQ(found, 2);  // ... and are not counted again as the run goes on.
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].count, 4);
}

TEST(ConsistentGroups, AGapOrAJumpStartsTheRunAgain) {
  std::vector<PlaceGroup> groups;
  int found = 0;
  ConsistentGroups({{0.5, 20}}, 3, &groups, &found);
  ConsistentGroups({{0.5, 21}}, 3, &groups, &found);
  ConsistentGroups({}, 3, &groups, &found);  // A keyframe that finds nothing breaks the run.
  EXPECT_TRUE(ConsistentGroups({{0.5, 22}}, 3, &groups, &found).empty());
  ConsistentGroups({{0.5, 23}}, 3, &groups, &found);
  // Another place, further than twice the reach: a run of its own.
  EXPECT_TRUE(ConsistentGroups({{0.5, 23 + 2 * PlaceGroups::kReach + 1}}, 3, &groups, &found).empty());
  EXPECT_EQ(found, 0);
}

TEST(ConsistentGroups, GroupsFarBelowTheBestAreDropped) {
  std::vector<PlaceGroup> groups;
  int found = 0;
  // Keyframe 50's group scores 0.9; keyframe 10's 0.6 < 0.75 * 0.9: only 50 is kept.
  ConsistentGroups({{0.9, 50}, {0.6, 10}}, 3, &groups, &found);
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].lo, 50 - PlaceGroups::kReach);
  EXPECT_EQ(groups[0].hi, 50 + PlaceGroups::kReach);
  EXPECT_TRUE(InSamePlace(50, 53));
  EXPECT_FALSE(InSamePlace(50, 54));
}

}  // namespace
}  // namespace dsm

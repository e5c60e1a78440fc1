// SPDX-License-Identifier: MIT
#include "dsm/place/place_index.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

TEST(PlaceIndex, ScoresTheKeyframesThatShareWordsAndForgetsRemovedOnes) {
  PlaceIndex index;
  index.Add(0, {{1, 0.5f}, {2, 0.5f}});
  index.Add(1, {{2, 0.5f}, {3, 0.5f}});
  index.Add(2, {{7, 1.0f}});
  const BowVector query = {{1, 0.25f}, {2, 0.75f}};
  const auto all = index.Query(query, 0.0, [](int) { return false; });
  // Keyframe 2 shares no word and is not scored; the scores are Vocabulary::Score's.
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].second, 0);
  EXPECT_NEAR(all[0].first, Vocabulary::Score(query, *index.Bow(0)), 1e-6);
  EXPECT_NEAR(all[0].first, 0.75, 1e-6);
  EXPECT_EQ(all[1].second, 1);
  EXPECT_NEAR(all[1].first, 0.5, 1e-6);
  EXPECT_EQ(index.Query(query, 0.6, [](int) { return false; }).size(), 1u);
  EXPECT_TRUE(index.Query(query, 0.0, [](int k) { return k <= 1; }).empty());
  index.Remove(0);
  EXPECT_EQ(index.Bow(0), nullptr);
  EXPECT_EQ(index.size(), 2u);
  const auto rest = index.Query(query, 0.0, [](int) { return false; });
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_EQ(rest[0].second, 1);
}

}  // namespace
}  // namespace dsm

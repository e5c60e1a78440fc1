// SPDX-License-Identifier: MIT
// The place index of a run's maps (atlas_places.h): each map's places answer only for that map,
// a merge moves them under the taking map's ids, and the merge candidates name their maps by a
// serial number that a map made later never takes over.
#include "dsm/system/atlas_places.h"

#include <gtest/gtest.h>

namespace dsm {
namespace {

// A map with no keyframes: the index only stores and compares bags of words.
class EmptyMap final : public PlaceMap {
 public:
  const Map& map() const override { return map_; }
  const OrbFeatures& KeyframeFeatures(int) override { return features_; }
  std::vector<ReferencePoint> PointsSeenIn(int) override { return {}; }

 private:
  Map map_;
  OrbFeatures features_;
};

const auto kNone = [](int) { return false; };

TEST(AtlasPlaces, EachMapIsAskedForItsOwnPlacesOnly) {
  AtlasPlaces places;
  EmptyMap a, b;
  places.Join(&a);
  places.Join(&b);
  places.Add(&a, 0, {{1, 0.5f}, {2, 0.5f}});
  places.Add(&b, 0, {{1, 0.5f}, {2, 0.5f}});
  places.Add(&b, 1, {{3, 1.0f}});
  const BowVector query = {{1, 0.5f}, {2, 0.5f}};
  const auto in_a = places.Query(&a, query, 0.1, kNone);
  ASSERT_EQ(in_a.size(), 1u);
  EXPECT_EQ(in_a[0].second, 0);
  EXPECT_NEAR(in_a[0].first, 1.0, 1e-6);
  const auto in_b = places.Query(&b, query, 0.1, kNone);
  ASSERT_EQ(in_b.size(), 1u);  // Keyframe 1 shares no word.
  EXPECT_EQ(places.Query(&b, {{3, 1.0f}}, 0.1, kNone).front().second, 1);
}

TEST(AtlasPlaces, AMergeMovesThePlacesUnderTheTakingMapsIds) {
  AtlasPlaces places;
  EmptyMap taker, taken;
  places.Join(&taker);
  places.Join(&taken);
  places.Add(&taker, 0, {{1, 1.0f}});
  places.Add(&taken, 0, {{7, 1.0f}});
  places.Add(&taken, 2, {{8, 1.0f}});
  places.MoveInto(&taken, &taker, 5);
  EXPECT_EQ(places.Bow(&taken, 0), nullptr);
  EXPECT_TRUE(places.Query(&taken, {{7, 1.0f}}, 0.1, kNone).empty());
  ASSERT_NE(places.Bow(&taker, 5), nullptr);
  ASSERT_NE(places.Bow(&taker, 7), nullptr);
  EXPECT_EQ(places.Query(&taker, {{8, 1.0f}}, 0.1, kNone).front().second, 7);
  EXPECT_NE(places.Bow(&taker, 0), nullptr);
}

TEST(AtlasPlaces, CandidatesKeepTheSerialTheirMapJoinedWithAndGoWithIt) {
  AtlasPlaces places;
  EmptyMap a, b;
  places.Join(&a);
  places.Join(&b);
  places.SetMergeCandidates({{4, &b}, {2, &a}});
  ASSERT_EQ(places.merge_candidates().size(), 2u);
  EXPECT_EQ(places.merge_candidates()[0].id, 4);
  EXPECT_EQ(places.merge_candidates()[0].map, &b);
  const int serial_b = places.merge_candidates()[0].serial;
  EXPECT_NE(serial_b, places.merge_candidates()[1].serial);
  places.Leave(&b);
  ASSERT_EQ(places.merge_candidates().size(), 1u);
  EXPECT_EQ(places.merge_candidates()[0].map, &a);
  // A map joining later (even at the address of one that left) gets a serial of its own.
  places.Join(&b);
  places.SetMergeCandidates({{5, &b}});
  EXPECT_NE(places.merge_candidates()[0].serial, serial_b);
  EXPECT_EQ(places.Bow(&b, 0), nullptr);  // Its places left with it.
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/mapping/occlusion.h"

#include <gtest/gtest.h>

#include "dsm/util/check.h"

namespace dsm {
namespace {

TEST(OcclusionGrid, TwoNearerNeighboursHideAPoint) {
  OcclusionGrid grid(640, 480, {});
  // A near object (1 m) around (100, 100); a wall at 4 m everywhere.
  for (int y = 0; y < 480; y += 10)
    for (int x = 0; x < 640; x += 10) grid.Add(Eigen::Vector2f(x, y), 0.25f);
  grid.Add(Eigen::Vector2f(98, 101), 1.f);
  grid.Add(Eigen::Vector2f(104, 96), 1.f);
  EXPECT_TRUE(grid.IsOccluded(Eigen::Vector2f(100, 100), 0.25f));   // The wall behind the object.
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(100, 100), 1.f));    // The object itself.
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(300, 300), 0.25f));  // Wall elsewhere.
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(100, 100), 0.8f));   // Barely behind: a slanted surface.
  // One near point (an outlier depth) hides nothing.
  grid.Add(Eigen::Vector2f(400, 400), 2.f);
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(401, 401), 0.25f));
  // Outside the image: never hidden.
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(-5, 10), 0.1f));
  EXPECT_FALSE(grid.IsOccluded(Eigen::Vector2f(700, 10), 0.1f));
}

TEST(OcclusionGrid, APlainPillarHidesTheWallBetweenItsEdges) {
  // A plain pillar (1 m) spans x 300 .. 420 over the whole height; it holds points only along its
  // two edges. The wall (4 m) has points everywhere else.
  OcclusionGrid grid(640, 480, {});  // span_px 96
  for (int y = 0; y < 480; y += 10)
    for (int x = 0; x < 640; x += 10)
      if (x < 300 || x > 420) grid.Add(Eigen::Vector2f(x, y), 0.25f);
  for (int y = 0; y < 480; y += 6) {
    grid.Add(Eigen::Vector2f(301, y), 1.f);
    grid.Add(Eigen::Vector2f(419, y), 1.f);
  }
  const Eigen::Vector2f middle(360, 200);
  EXPECT_TRUE(grid.IsBetween(middle, 0.25f));    // The wall behind the pillar's middle.
  EXPECT_FALSE(grid.IsOccluded(middle, 0.25f));  // Its edges are too far for the 3 x 3 cells alone.
  EXPECT_FALSE(grid.IsBetween(middle, 1.f));     // The pillar itself.
  EXPECT_FALSE(grid.IsBetween(Eigen::Vector2f(200, 200), 0.25f));  // Wall beside it: one side only.
  EXPECT_FALSE(grid.IsBetween(Eigen::Vector2f(520, 200), 0.25f));
  // A pillar wider than twice the span leaves its middle.
  OcclusionGrid wide(640, 480, {});
  for (int y = 0; y < 480; y += 6) {
    wide.Add(Eigen::Vector2f(101, y), 1.f);
    wide.Add(Eigen::Vector2f(539, y), 1.f);
  }
  EXPECT_FALSE(wide.IsBetween(Eigen::Vector2f(320, 200), 0.25f));
}

TEST(OcclusionOptions, BadValuesAreRefused) {
  OcclusionOptions o;
  o.depth_ratio = 1.f;
  EXPECT_THROW(o.Validate(), InputError);
  o = {};
  o.min_occluders = 0;
  EXPECT_THROW(o.Validate(), InputError);
  o = {};
  o.cell_px = 0;
  EXPECT_THROW(o.Validate(), InputError);
  o = {};
  o.span_px = 0;
  EXPECT_THROW(o.Validate(), InputError);
  o = {};
  o.texture_check = "sometimes";
  EXPECT_THROW(o.Validate(), InputError);
  for (const char* check : {"none", "between", "all"}) {
    o.texture_check = check;
    EXPECT_NO_THROW(o.Validate());
  }
  for (const float interval : {-0.1f, 1.f}) {
    o = {};
    o.candidate_interval = interval;
    EXPECT_THROW(o.Validate(), InputError) << interval;
  }
  o = {};
  o.candidate_interval = 0.25f;
  EXPECT_NO_THROW(o.Validate());
  EXPECT_NO_THROW(OcclusionOptions{}.Validate());
}

}  // namespace
}  // namespace dsm

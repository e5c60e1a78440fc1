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

TEST(OcclusionOptions, BadValuesAreRefused) {
  OcclusionOptions o;
  o.depth_ratio = 1.f;
  EXPECT_THROW(o.Validate(), InputError);
  EXPECT_NO_THROW(OcclusionOptions{}.Validate());
}

}  // namespace
}  // namespace dsm

// SPDX-License-Identifier: MIT
// The temporal part of the local window (paper IV): the newest keyframes, kept at N_t by dropping
// one when a new keyframe arrives. The newest two always stay. First dropped is any other keyframe
// that has become useless — under `min_visible_ratio` of its points observed in the newest
// keyframe, or a brightness change |a_i - a_newest| above `max_affine_change` — otherwise the one
// maximising (paper eq. 6)
//   s(i) = sqrt(d(newest, i)) * sum_{j != i} 1 / d(i, j),     d = distance between camera centres,
// which keeps the remaining keyframes spread out in space.
#pragma once

#include <vector>

#include "dsm/map/map.h"

namespace dsm {

struct WindowOptions {
  int temporal_keyframes = 4;  // N_t, including the newest.
  static constexpr double min_visible_ratio = 0.05;
  static constexpr double max_affine_change = 0.7;
  // Covisible part (covisibility.h). DSM-SW (MapMode::kSlidingWindow) has none and a temporal
  // part of N_t + N_c keyframes instead.
  int covisible_keyframes = 5;         // N_c (3 in the paper, which re-uses too little of the map here).
  bool optimize_covisible_poses = false;  // Paper: true. Held, their points are still optimised.
  float depleted_distance_px = 2.f;    // A pixel this far from every projected point is depleted.
  static constexpr double max_view_angle_deg = 60.0;
  static constexpr double min_covisible_ratio = 0.05;   // Of a keyframe's points that must land in depleted areas.
  static constexpr float max_scale_change = 1.3f;        // Old points seen at a similar scale count as mapped places.

  void Validate() const;
};

// `window` holds keyframe ids, oldest first, the newest last. Returns the id to drop, or -1 when
// the window is not over its size.
int SelectKeyframeToDrop(const Map& map, const std::vector<int>& window, const WindowOptions& options);

// Share of the points hosted by `keyframe` (not removed) with a good observation in `target`.
double VisibleRatio(const Map& map, int keyframe, int target);

}  // namespace dsm

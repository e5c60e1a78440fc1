// SPDX-License-Identifier: MIT
// The covisible part of the local window (paper IV, second part). With the temporal keyframes'
// points projected into the newest keyframe, a distance map marks the depleted areas (no point
// within `depleted_distance_px`). Among the old keyframes (not temporal), pick greedily the one
// whose points fall most often into depleted areas — skipping points whose viewing angle changed
// by more than `max_view_angle_deg` (likely occluded or looking different) — add its points to the
// distance map and repeat, up to N_c keyframes. A keyframe qualifies only if that count is above
// `min_covisible_ratio` of its points. The chosen keyframes and their points join the bundle
// adjustment, so a revisited place re-uses its map instead of creating new points.
#pragma once

#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"
#include "dsm/mapping/activation.h"
#include "dsm/mapping/window.h"

namespace dsm {

struct CovisibleChoice {
  int keyframe = -1;
  int depleted_points = 0;  // Its points in depleted areas when it was chosen.
};

struct CovisibleSelection {
  std::vector<CovisibleChoice> chosen;  // Best first.
  // The points of the old keyframes not chosen that pass the same tests (ids and pixels in the
  // newest keyframe): where they are visible, the map already covers the place.
  std::vector<int> other_old_points;
  std::vector<Eigen::Vector2f> other_old_pixels;
};

// `temporal`: the temporal window (newest last). `distance`: the temporal points' projections in
// the newest keyframe on entry; the chosen keyframes' points are added to it.
CovisibleSelection SelectCovisibleKeyframes(const Map& map, const PinholeCamera& camera, const std::vector<int>& temporal,
                                            const WindowOptions& options, DistanceMap* distance);

}  // namespace dsm

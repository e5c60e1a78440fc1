// SPDX-License-Identifier: MIT
// What one photometric bundle adjustment (pba.h) solves over: its cameras, which of them stay
// fixed, and per point of an active keyframe the observations that enter.
//
// The cameras are the active keyframes, then the keyframes outside them that the points are
// observed in (fixed; at most `max_outside_keyframes`, the most observed). Fixed as well: keyframe
// 0 (the gauge), the `held` ones, and any camera in fewer than `min_camera_observations`
// observations (hosted or observed), which the data barely constrain, or in fewer than
// `min_link_ratio` times the most that tied it in an earlier solve that left it free
// (Keyframe::most_pba_links, which RunPba raises to `links` for the free cameras). A point of a held
// keyframe keeps its observations in active keyframes and the newest `max_outside_observations`
// outside them (they join two fixed poses and constrain only its depth); a point of another
// active keyframe keeps all its observations. A frozen keyframe (Keyframe::frozen) is fixed, and
// its points keep only their observations in keyframes that are not frozen: the others join two
// fixed poses and a fixed depth, a constant the adjustment cannot change.
#pragma once

#include <vector>

#include "dsm/map/map.h"
#include "dsm/optimization/pba.h"

namespace dsm {

struct PbaSelection {
  std::vector<int> cams;    // Keyframe ids; a problem camera index is a position here.
  std::vector<bool> fixed;  // Per camera.
  struct PointObservations {
    int id = -1;               // Point id.
    int host = -1;             // Camera index.
    std::vector<int> targets;  // Camera indices, one per observation in the problem.
  };
  std::vector<PointObservations> points;  // Only points with at least one observation.
  int num_observations = 0;
  std::vector<int> links;  // Per camera: the observations (hosted or observed) that tie it.
};

PbaSelection SelectPbaProblem(const Map& map, const std::vector<int>& active, const std::vector<int>& held,
                              const PbaOptions& options);

}  // namespace dsm

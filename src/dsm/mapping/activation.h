// SPDX-License-Identifier: MIT
// Activation of candidates into map points (paper VI-C, IV).
//
// A candidate qualifies when its last epipolar match was good, its pixel interval is short and
// its quality high. Its inverse depth is then refined by Gauss–Newton on the photometric
// residuals (8-pixel pattern, fixed poses) against the other window keyframes, and it is activated
// only if the newest keyframe's distance map marks its projection as depleted: no active point
// within `min_distance_px`. The distance map holds, per pixel (at half resolution), the distance
// to the nearest projected active point; it is updated as points are added.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"
#include "dsm/mapping/candidate.h"

namespace dsm {

struct ActivationOptions {
  int target_points = 1500;        // Active points wanted in the window.
  static constexpr float max_pixel_interval = 8.f;  // Of the last epipolar match.
  static constexpr float min_quality = 2.f;
  static constexpr int refine_iterations = 5;
  static constexpr float min_inlier_ratio = 0.7f;   // Of a target observation after the refinement.
  static constexpr float initial_min_distance_px = 6.f;

  void Validate() const;
};

class DistanceMap {
 public:
  DistanceMap(int width, int height);  // Level-0 size; stored at half resolution.
  void Add(const Eigen::Vector2f& pixel);  // Level-0 pixel of an active point.
  float Distance(const Eigen::Vector2f& pixel) const;  // Level-0 pixels to the nearest point.

 private:
  int w_, h_;
  std::vector<float> d_;  // Half-resolution distances (level-0 units).
};

struct RefinedPoint {
  float idepth = 0.f;
  std::vector<int> targets;  // Keyframes where the refined point is an inlier.
};

// Refines the candidate hosted by `host` against `targets`; false when it does not converge to a
// point seen as an inlier in at least one target.
bool RefineCandidate(const Map& map, const PinholeCamera& camera, int host, const Candidate& candidate,
                     const std::vector<int>& targets, const ActivationOptions& options, RefinedPoint* out);

}  // namespace dsm

// SPDX-License-Identifier: MIT
// New keyframe decision (paper VI-B). With the tracked frame relative to the newest keyframe:
//   s_t = |t| * mean inverse depth      (parallax)
//   s_u = mean over points of min(rho_kf / rho_frame, 1), 0 when out of view   (visibility)
//   s_a = |alpha - log(tau_frame / tau_kf)|   (illumination change beyond the known exposure)
// A keyframe is created when  w_t s_t + w_u (1 - s_u) + w_a s_a > 1, or when the tracking residual
// exceeds `residual_growth` times that of the first frame tracked after the newest keyframe.
#pragma once

namespace dsm {

struct KeyframeOptions {
  double weight_parallax = 4.0;
  double weight_visibility = 3.0;
  double weight_brightness = 4.0;
  static constexpr double residual_growth = 2.0;

  void Validate() const;
};

struct KeyframeScores {
  double parallax = 0.0, visibility = 1.0, brightness = 0.0;
  double rmse = 0.0, first_rmse = 0.0;  // This frame's, and the first frame's after the keyframe.
};

bool ShouldCreateKeyframe(const KeyframeScores& s, const KeyframeOptions& options);

}  // namespace dsm

// SPDX-License-Identifier: MIT
// The tracking-quality test: whether a frame's pose can be trusted. A frame that fails it is
// *lost*: it gets no pose, never becomes a keyframe and never feeds the candidates or the PBA.
//
// The levels a frame is compared with are running medians over the last `history` trusted frames,
// so the test follows the sequence (a render with sensor noise and a camera image differ 10x in
// residual) instead of absolute thresholds:
//   image:    texture < min_texture_ratio x texture level         (black, saturated, covered lens)
//            while lost, texture < min_relocalisation_texture_ratio x the level before (a hand
//            half over the lens, or a plainer part of the scene): any pose fits the rest of a
//            half-covered frame as well as the right one, so such a frame relocalises only by
//            three sightings that move as one camera (TrackingSide::Relocalise, `plain`).
//            The level there is the lower of the running one and the newest keyframe's (the
//            last view of the place, made before a hand came in: a frame whose texture fell
//            makes no keyframe): the running median lags a view turning to a plainer part of
//            the scene, and frames after a blackout are then tried against the map sooner.
//            (Tracked camera frames stay above 0.8 of the level; a hand over half the view
//            leaves about half.)
//   keyframe: a tracked frame whose texture fell below min_keyframe_texture_step x the frame
//            before's makes no keyframe (a hand sliding over the lens, a blurred frame); the next
//            frame decides again, so a texture that falls for good stops none.
//   tracking: median |residual| > max_residual_ratio x its level   (noise, a wrong minimum)
//             inlier_ratio < min_inlier_ratio                      (most of the view changed)
//             rotation of the step from the last trusted frame > max_rotation_deg per frame
//             between them (no hand or vehicle turns that fast; a diverged alignment does)
//             parallax against the reference, |t| x mean inverse depth of its points, > max_parallax
//             (keyframes come at 1/4; an alignment that ran off to infinity projects every point
//             onto the epipole and leaves a small residual)
//   relocalisation against a keyframe other than the one the camera was lost from: median
//             |residual| > max_relocalisation_residual_ratio x the level instead. The level is
//             measured against the newest keyframe, a few frames away; an older keyframe sees the
//             place from further off and in other light (correct poses against keyframes far
//             back show several times the level, wrong minima an order of magnitude more)
//   relocalisation, besides: the camera moved from the last trusted pose by more than
//             (frames) x (max_speed_ratio x its speed before + min_speed x mean depth), or its
//             turn differs from the constant-velocity prediction by more than (frames) x
//             min_turn_deg (a repetitive scene offers a second place that looks the same, and
//             its residual can pass the test)
// The levels judge once they hold `min_history` values. A new map's are seeded at once
// (TrackingSide::StartMap): the texture with that of each frame the initialiser used, the residual with
// the frame before the second keyframe tracked against the new map, so that a bad frame right
// after the start is judged as any other.
// The median of the level-0 gradient-weighted residuals (TrackResult::residual_p50), not their
// RMS: occlusions and moving things add outliers to a good alignment and raise its RMS, while a
// frame of noise or an alignment in a wrong minimum moves the median itself, by an order of
// magnitude.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "dsm/lie/se3.h"
#include "dsm/tracking/frame_tracker.h"

namespace dsm {

struct QualityOptions {
  double min_texture_ratio = 0.35;
  double min_relocalisation_texture_ratio = 0.7;
  static constexpr double min_keyframe_texture_step = 0.8;
  double max_residual_ratio = 4.0;
  static constexpr double max_relocalisation_residual_ratio = 6.0;
  static constexpr double min_inlier_ratio = 0.5;
  double max_rotation_deg = 25.0;
  static constexpr double max_parallax = 1.5;
  static constexpr double max_speed_ratio = 2.0;
  static constexpr double min_speed = 0.02;
  static constexpr double min_turn_deg = 2.5;
  int history = 20;
  static constexpr int min_history = 3;

  void Validate() const;
};

class TrackingQuality {
 public:
  explicit TrackingQuality(const QualityOptions& options);

  // Empty when a frame of this texture (FrameSignature::texture) may be tracked, else why not.
  std::string CheckImage(double texture) const;
  // Whether a tracked frame of this texture may become a keyframe after a frame of `previous`.
  bool CheckKeyframeImage(double texture, double previous) const;
  // Empty when a lost frame of this texture has the usual texture, else why not (it then
  // relocalises only by three sightings); `keyframe_texture`: the newest keyframe's (0: unknown).
  std::string CheckRelocalisationImage(double texture, double keyframe_texture = 0.0) const;
  // Empty when the tracked frame can be trusted, else why not. `step`: its motion from the last
  // trusted frame (frame_from_last), `frames` frames after it; `mean_idepth`: of the reference's points.
  // `other_keyframe`: a relocalisation against a keyframe other than the last reference.
  std::string CheckTracking(const TrackResult& result, const SE3d& step, int frames, double mean_idepth,
                            bool other_keyframe = false) const;
  // Empty when a relocalised pose is within reach of the last trusted one: `step` from it (as in
  // CheckTracking), `frames` later; `velocity`: the camera's motion per frame before it was lost;
  // `mean_idepth`: of the reference's points.
  std::string CheckJump(const SE3d& step, int frames, const SE3d& velocity, double mean_idepth) const;
  // CheckJump's reach alone, for a camera moving `speed` per frame (translation, map units).
  std::string CheckSpeed(const SE3d& step, int frames, double speed, double mean_idepth) const;
  // A trusted frame: its values join the levels (inlier_ratio < 0: not known).
  void Trust(double residual_p50, double texture, double inlier_ratio = -1.0);
  // A new map's levels before its first trusted frame: the initialiser's frames' textures and
  // one frame's residual against the new map (<= 0: none; min_history copies of it).
  void Seed(double residual_p50, const std::vector<double>& textures);
  // A relocalised frame: its reference is another keyframe, often a farther one than tracking
  // uses, so its residual level starts again from this frame's (never below the old level).
  void Restart(double residual_p50, double texture);

  double ResidualLevel() const;  // 0 before the first trusted frame.
  double InlierLevel() const;    // Of TrackResult::inlier_ratio; 0 before min_history values.
  double TextureLevel() const;  // 0 before the first trusted frame.

 private:
  // Whether the texture level is known (`min_history` values) and `texture` is below `ratio` x
  // `level` (the level, or a lower one taken for it).
  bool BelowTextureLevel(double texture, double ratio, double level) const;

  QualityOptions options_;
  std::deque<double> residual_, texture_, inliers_;
};

}  // namespace dsm

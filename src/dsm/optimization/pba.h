// SPDX-License-Identifier: MIT
// Photometric bundle adjustment (paper III-B, V): Levenberg–Marquardt over the active keyframes
// (pose 6 + affine 2) and the points they host (inverse depth), coarse to fine over pyramid
// levels, with per-keyframe robust error models and pixel-wise outlier masks.
//
//   E = sum_points sum_obs sum_k rho_t( sqrt(w_g) r_k )        (rho_t: the target keyframe's model)
//
// Gauge: keyframe 0 (the oldest of the map) never moves; keyframes observed by active points but
// not active themselves are in the problem and fixed (at most `max_outside_keyframes` of them,
// the most observed); so is an active keyframe in fewer than
// `min_camera_observations` observations (hosted or observed), which the data barely constrain
// (pba_selection.h chooses the cameras, points and observations).
// The error model of every keyframe is refitted at the start of each level and after the last one
// (stored in the keyframe). Its scale is bounded by `max_sigma_ratio` times the median scale of the
// problem's keyframes: image noise and the change of appearance between views are shared by the
// keyframes of one window (one camera, one part of the scene), so a keyframe whose residuals spread
// several times wider is one whose residuals are dominated by misalignment — a frame tracked wrong
// as a near object swept through the view. Fitted freely, its model widens to them and its pixel
// masks accept the observations of points hidden behind the near object; its points then become
// the tracking reference and the scale breaks. Three times the median leaves the models of
// well-aligned keyframes alone.
// Linearisation accumulates Hessian blocks per host–target keyframe pair in parallel chunks that
// are summed in a fixed order, so results do not depend on the thread schedule.
#pragma once

#include <functional>
#include <vector>

#include "dsm/geometry/camera.h"
#include "dsm/map/map.h"
#include "dsm/photometric/robust.h"
#include "dsm/photometric/texture_loss.h"

namespace dsm {

struct PbaOptions {
  int levels = 2;              // Pyramid levels, coarse to fine: levels-1 .. 0 (N_p of the paper).
  int max_iterations = 12;     // Per level (6 costs accuracy on the synthetic corridor, 30 buys nothing).
  double initial_lambda = 1e-4;
  int min_camera_observations = 50;  // An active keyframe in fewer observations stays fixed.
  // So does one in fewer than this share of the most observations that tied it in an earlier
  // solve that moved it (Keyframe::most_pba_links; 0: never).
  double min_link_ratio = 0.3;
  int max_outside_observations = 3;  // Per point of a held keyframe: the newest ones outside the window.
  // Keyframes outside the window in the problem (fixed): the most observed ones; 0: all. Bounds
  // the problem as the map grows (16 or 24 cost accuracy on the synthetic orbit and forward).
  int max_outside_keyframes = 32;
  RobustOptions robust;
  static constexpr double drop_outlier_ratio = 0.3;  // After the PBA: > 30% bad pixels removes the observation.
  static constexpr double skip_outlier_ratio = 0.6;  // During it: > 60% bad pixels gives the observation weight 0.
  // With texture_loss.max_variance_ratio > 0 (off by default; the system sets it on images as
  // noisy as system.texture_loss_min_noise), an observation whose target shows
  // no trace of the host's texture (texture_loss.h) at the finest level is left out of the error
  // models' fit and removed after the PBA; it stays in the energy, so that a pattern that misses
  // its texture while the point's depth converges is still pulled into place.
  TextureLossOptions texture_loss;
  // A keyframe's fitted scale sigma is at most this many times the median over the problem's
  // keyframes (0: unbounded; see RunPba).
  double max_sigma_ratio = 3.0;
  // Refit the error model of every keyframe in the problem to its current residuals (true), or
  // only the newest keyframe's (false, as the original DSM), to the residuals of points hosted by
  // free keyframes: an older keyframe then keeps the model fitted when it was the newest, and
  // re-observations of held or fixed keyframes' points, which may disagree at a lap's end, do not
  // widen it.
  bool refit_all_models = true;
  // Convergence: every component of the last step below these (translation scaled by the mean
  // inverse depth of the points).
  double max_rotation_step = 6e-5, max_translation_step = 6e-5, max_a_step = 6e-4, max_b_step = 0.06;

  void Validate() const;  // Throws InputError naming the option.
};

// An adjustment that may stop between two iterations so that other work runs first, and be taken
// up later where it stopped: every accepted step is in the map meanwhile, and the later call builds
// its problem from the map as it is then.
struct PbaYield {
  std::function<bool()> now;  // Asked after every iteration but the last: true stops there.
  int level = -1;             // Take up at this level (-1: start at the coarsest), ...
  int iterations = 0;         // ... where this many of its iterations were done.
};

struct PbaSummary {
  int iterations = 0;
  // Stopped by PbaYield::now at `level` after `level_iterations` of its iterations (the outlier
  // marking and the models' final fit are left to the call that takes it up).
  bool yielded = false;
  int level = 0, level_iterations = 0;
  int keyframes = 0, fixed_keyframes = 0, points = 0, observations = 0;
  std::vector<int> cameras;  // The keyframes in the problem, free or fixed (ids).
  double initial_energy = 0.0, final_energy = 0.0;  // Of the finest level (same models), before / after.
  int observations_removed = 0;
  int observations_texture_lost = 0;  // Of those removed: the texture vanished in the target.
  double time_ms = 0.0;
};

// Optimises the keyframes `active` (ids) and their points; the poses of those also in `held` stay
// fixed (their points are optimised). Returns what it did.
PbaSummary RunPba(Map* map, const PinholeCamera& camera, const std::vector<int>& active, const PbaOptions& options,
                  const std::vector<int>& held = {}, const PbaYield& yield = {});

}  // namespace dsm

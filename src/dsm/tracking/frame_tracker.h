// SPDX-License-Identifier: MIT
// Frame tracking (paper VI-A): the pose and brightness of a new frame relative to the newest
// keyframe, by direct image alignment of the window's points projected into that keyframe.
//
// Each point u of the reference (the keyframe) with inverse depth rho contributes its 8 pattern
// pixels u_k, predicted in the frame at  u'_k = pi( T pi^-1(u_k, rho) ),  T = frame_from_keyframe:
//   r_k = I_f(u'_k) - e^alpha I_r(u_k) - beta.
// On the coarse levels (>= kFirstCentreOnlyLevel) only the pattern's centre pixel is used: the
// pattern would cover several pixels of the finer levels anyway.
// Inverse compositional Gauss–Newton/LM on the pose: the geometric Jacobian is taken on the
// reference, J_k = -e^alpha grad I_r(u_k) J_pi(p_k) [I  -hat(p_k)], fixed per level; the update
// is T <- T Exp(delta)^-1. (alpha, beta) are updated additively (or held: see Track). Weights:
// gradient weight times a Student-t fitted per level. Coarse to fine over the pyramid.
//
// The Jacobian of pixel k over (xi, alpha, beta) is J_k = -D g_k with the fixed
//   g_k = (grad I_r J_pi [I -hat(p_k)], I_r(u_k), 1),   D = diag(e^alpha (x7), 1),
// so the normal equations are H = D (sum_k w_k g_k g_k^T) D and b = -D sum_k w_k g_k r_k: per
// iteration only the weights and residuals change. Each evaluation projects and samples every
// pixel once; the energy decides whether a step is taken, and the sums are formed only then
// (single precision within fixed chunks, added in double in chunk order: deterministic).
// The per-pixel loops are compiled for AVX2 as well, picked at load time (util/simd.h).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dsm/geometry/camera.h"
#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/photometric/residual.h"
#include "dsm/photometric/robust.h"
#include "dsm/tracking/rolling_shutter.h"

namespace dsm {

constexpr int kFirstCentreOnlyLevel = 2;

struct TrackerOptions {
  int levels = 4;                               // Coarse to fine: levels-1 .. 0.
  std::vector<int> iterations = {10, 20, 50, 75};  // Per level, index = level.
  RobustOptions robust = TrackerRobustDefaults();
  // Lost below this share of usable points. Keyframes come long before tracking gets near it; it
  // bounds what a relocalisation may keep in view: a camera back after a gap may see a tenth of
  // the last keyframe's points or less, and a pose from 4% of a window's points (some 60 points of
  // 8 pixels) is still determined; whether it is right is the quality test's to judge.
  double min_usage = 0.04;
  // A level is done once a step would move the image by less than this (pixels of that level,
  // bound at the image centre: |w| f + |v| f mean_idepth), accepted or not: smaller steps are
  // below what the sampled energy resolves, and LM would only raise its damping on them.
  static constexpr double convergence_px = 0.01;
  // The reference: the window's points with a verified (inlier) observation in the keyframe, as
  // the bundle adjustment left them; false: every point that projects into it. A point hidden in
  // the keyframe would take the intensity of what hides it at its own depth.
  bool verified_reference = true;
  // Largest change of log contrast alpha from the guess per frame that Track believes (see
  // Track). Exposure changes between frames move it by < 0.1 once the exposure times are
  // accounted for.
  static constexpr double max_alpha_step = 0.4;
  // Frames of that change at most, however many frames apart the guess is: a few dropped or
  // lost frames are no time for the contrast to halve, but at 0.4 per frame they would be enough
  // for the flat prediction's alpha (-1 ... -3) to pass.
  static constexpr int max_alpha_frames = 2;

  // The t-fit runs at every level of every frame: a smaller sample than the PBA's.
  static RobustOptions TrackerRobustDefaults() {
    RobustOptions r;
    r.max_fit_samples = 600;
    return r;
  }

  void Validate() const;
};

// A reference point: level-0 pixel in the keyframe and inverse depth.
struct ReferencePoint {
  Eigen::Vector2f pixel;
  float idepth = 1.f;
};

struct TrackResult {
  bool ok = false;
  std::string reason;             // Why tracking failed, when it did.
  SE3d frame_from_keyframe;
  double alpha = 0.0, beta = 0.0; // I_f = e^alpha I_r + beta (relative brightness)
  double rmse = 0.0;              // Of the gradient-weighted residuals at level 0.
  double inlier_ratio = 0.0;      // Share of level-0 pixels within the fitted model's inlier threshold.
  double residual_p50 = 0.0;      // Median of the level-0 |sqrt(w_g) r| at the result.
  ErrorModel model;               // Fitted to the level-0 residuals.
  double usage = 0.0;             // Share of reference points whose patch lands in the frame.
  double visibility = 0.0;        // s_u = mean min(rho_kf / rho_frame, 1), 0 out of view (paper VI-B).
  int iterations = 0;
  bool brightness_held = false;   // Tracked again with the brightness held (see FrameTracker::Track).
};

class FrameTracker {
 public:
  explicit FrameTracker(const TrackerOptions& options);

  // Sets the reference keyframe (its pyramid must outlive the tracker's use) and its points.
  void SetReference(const ImagePyramid* keyframe, const PinholeCamera& camera, const std::vector<ReferencePoint>& points);
  int NumReferencePoints() const { return static_cast<int>(points_.size()); }
  // Mean inverse depth of the reference points (for the parallax score).
  double MeanIdepth() const { return mean_idepth_; }

  // Tracks `frame` starting at the guess (pose and brightness relative to the reference), made
  // `frames` frames after the one the guess comes from. A result whose contrast moved from the
  // guess by more than options.max_alpha_step per frame (over at most max_alpha_frames frames)
  // is no exposure change: the alignment traded contrast for fit (under heavy-tailed weights a
  // flat prediction, e^alpha -> 0 and beta -> the mean intensity, fits an image the points do not
  // match yet, and holds the pose there).
  // The pose is then tracked again with (alpha, beta) held at the guess (brightness_held).
  // With `turn`, the frame's pixels are predicted where a rolling shutter saw them, and the pose
  // is the camera's at the frame's timestamp (its first row's).
  TrackResult Track(const ImagePyramid& frame, const SE3d& guess, double alpha_guess, double beta_guess,
                    int frames = 1, const ReadoutTurn& turn = {}) const;

  // Energy of the guess at the coarsest level (to rank alternative guesses cheaply).
  double CoarseEnergy(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta) const;
  // As CoarseEnergy, but the mean over all points: one that leaves the frame costs as much as a
  // residual at the inlier threshold. Ranks guesses that may turn much of the map out of view
  // (relocalisation after the camera moved on), where CoarseEnergy gives up below half.
  double CoarseEnergyOverAll(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta) const;

 private:
  using Vector8f = Eigen::Matrix<float, 8, 1>;
  // Per pattern pixel of the reference, at one level.
  struct LevelData {
    PinholeCamera camera;
    std::vector<float> qx, qy;          // K^-1 (u_k, 1) at the level
    std::vector<float> idepth;
    std::vector<float> grad_weight;     // w_g, and its square root
    std::vector<float> sqrt_grad_weight;
    std::vector<Vector8f, Eigen::aligned_allocator<Vector8f>> g;  // (grad I_r J_pi [I -hat(p)], I_r, 1): g(6) = I_r
  };
  // Residuals r_k = I_f(u'_k) - e^alpha I_r - beta of every pixel of a level at one state (0 where
  // the pixel leaves the frame), and what they sum to under an error model.
  struct Residuals {
    std::vector<float> r;
    std::vector<float> valid;  // 1 or 0
    std::vector<float> u, v;   // Where the pixels project (scratch).
  };
  struct Energy {
    double energy = 0.0, sum_sq = 0.0;  // Robust energy and sum of squares of sqrt(w_g) r
    int valid = 0, bad = 0;
    double Mean() const { return valid > 0 ? energy / valid : std::numeric_limits<double>::infinity(); }
  };
  struct System8 {
    Eigen::Matrix<double, 8, 8> H = Eigen::Matrix<double, 8, 8>::Zero();
    Eigen::Matrix<double, 8, 1> b = Eigen::Matrix<double, 8, 1>::Zero();
  };
  void Evaluate(int level, const ImagePyramid& frame, const SE3d& T, double alpha, double beta, Residuals* out,
                const ReadoutTurn& turn = {}) const;
  Energy SumEnergy(int level, const Residuals& res, const ErrorModel& model) const;
  // One coarse-to-fine alignment; `hold_brightness`: the pose alone.
  TrackResult TrackOnce(const ImagePyramid& frame, const SE3d& guess, double alpha_guess, double beta_guess,
                        bool hold_brightness, const ReadoutTurn& turn) const;
  // The energy of the coarsest level at one state, unoptimised (CoarseEnergy, CoarseEnergyOverAll).
  Energy CoarseSum(const ImagePyramid& frame, const SE3d& guess, double alpha, double beta, const ErrorModel& model) const;
  System8 SumSystem(int level, const Residuals& res, const ErrorModel& model, double alpha) const;

  TrackerOptions options_;
  std::vector<LevelData> levels_;
  std::vector<ReferencePoint> points_;
  double mean_idepth_ = 1.0;
};

}  // namespace dsm

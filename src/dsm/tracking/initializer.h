// SPDX-License-Identifier: MIT
// Monocular map initialisation from the first frames.
//
// Corners of the reference frame are tracked frame to frame (pyramidal KLT). For each new frame the
// relative motion is estimated from the tracks with an essential matrix (RANSAC) and checked
// against a homography: a motion is accepted only when
//   * enough tracks are inliers of the essential matrix and in front of both cameras,
//   * the median triangulation angle (parallax) exceeds `min_parallax_deg`,
//   * the homography does not explain the tracks nearly as well (pure rotation, or too little
//     parallax for the essential matrix to mean anything).
// Otherwise it waits for more motion. The translation is scaled so that the median depth of the
// triangulated points in the reference frame is 1.
//
// A hand-held start that sees mostly one plane (a wall) never passes the homography check, and its
// essential matrix is ill-posed. So when the homography explains the tracks, its decomposition
//   H ~ R + t n^T / d     (plane n^T X = d in the reference frame)
// is used (`planar_start`) once it explains nearly every track the essential matrix does
// (`planar_min_homography_ratio`; below it, the tracks off the plane soon give the essential
// matrix its parallax): of its four solutions, those that put the inlier tracks in front of
// both cameras remain, in general two — the true one and its twin, whose normal follows the
// direction of motion. The true plane is the same for every frame, the twin's normal moves as the
// hand changes direction, so a solution is taken when its normal agrees with one from a frame at
// least `planar_frame_gap` frames earlier (within `planar_normal_tolerance_deg`) and its twin's
// does not (beyond 3x that), and |t| / d exceeds the parallax bound (tan(min_parallax_deg)).
// The tracks the homography explains then lie on the plane: depth d / (n^T x) along their rays x.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "dsm/geometry/camera.h"
#include "dsm/image/image.h"
#include "dsm/lie/se3.h"

namespace dsm {

struct InitializerOptions {
  static constexpr int max_corners = 800;
  double min_parallax_deg = 1.5;
  static constexpr double max_homography_ratio = 0.9;  // Refuse when H inliers / E inliers exceed this.
  static constexpr int min_inliers = 60;
  static constexpr double ransac_threshold_px = 1.0;
  bool planar_start = true;           // Start from the homography when one plane fills the view.
  static constexpr double planar_min_homography_ratio = 0.98;
  static constexpr int planar_frame_gap = 4;
  static constexpr double planar_normal_tolerance_deg = 3.0;
  // The caller starts over on the current frame once fewer than this share of the reference's
  // corners are still tracked (TrackingSide::Initialize): a camera that moves fast, or a live one whose
  // frames are dropped while the initialiser waits for parallax, loses most corners within a few
  // frames, and two views joined by the few that remain make a map of a hundred points whose scale
  // collapses within a few keyframes. A normal start keeps well above this share.
  double min_track_share = 0.3;

  void Validate() const;
};

struct InitPoint {
  Eigen::Vector2f pixel;  // In the reference frame, level 0.
  float idepth = 1.f;
};

struct InitResult {
  bool ok = false;
  std::string reason;             // Why this frame did not initialise.
  SE3d current_from_reference;
  std::vector<InitPoint> points;  // Triangulated inliers.
  double parallax_deg = 0.0;
  double homography_ratio = 0.0;
  bool planar = false;  // Started from the homography's plane.
};

class Initializer {
 public:
  explicit Initializer(const InitializerOptions& options);

  // Starts over with `image` (undistorted, level 0) as the reference frame.
  void SetReference(const Image<float>& image, const PinholeCamera& camera);
  bool HasReference() const { return has_reference_; }
  int NumTracks() const;
  // Share of the reference's corners still tracked (1 right after SetReference).
  double TrackShare() const;

  // Tracks the corners into `image` and tries to initialise.
  InitResult AddFrame(const Image<float>& image);

 private:
  // Moves the live corners into `gray` (chained KLT, then directly from the reference).
  void TrackCorners(const Image<uint8_t>& gray);
  // The planar start from the homography H (pixels) and its inlier tracks (reference positions,
  // h_mask): records the normals of its solutions and, if `accept` (the homography explains the
  // tracks), fills `result` when a solution is taken (see the header comment).
  bool PlanarStart(const cv::Mat& H, const std::vector<cv::Point2f>& ref, const cv::Mat& h_mask, bool accept,
                   InitResult* result);

  InitializerOptions options_;
  PinholeCamera camera_;
  bool has_reference_ = false;
  std::vector<Eigen::Vector2f> reference_corners_;
  std::vector<Eigen::Vector2f> current_corners_;
  std::vector<bool> alive_;
  Image<uint8_t> reference_;
  Image<uint8_t> previous_;
  // Per frame added since the reference: the plane normals of the homography's solutions in front
  // of both cameras.
  std::vector<std::vector<Eigen::Vector3d>> plane_normals_;
};

}  // namespace dsm

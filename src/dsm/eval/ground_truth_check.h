// SPDX-License-Identifier: MIT
// Does a dataset's ground truth agree with its images? Corners are tracked (KLT, forward-backward
// checked) between frame pairs (i, i + gap); every track (x1, x2) in normalized coordinates must
// satisfy the epipolar constraint of the ground-truth relative pose
//   cam2_from_cam1 = (R, t),   E = [t]x R,   x2^T E x1 = 0.
// The Sampson distance (x2^T E x1)^2 / (|(E x1)_xy|^2 + |(E^T x2)_xy|^2), taken to pixels by the
// focal length, is ~0.3 px with a correct ground truth and tens of pixels with a wrong frame
// convention (body vs camera, Hamilton vs JPL quaternions). The check runs on the images alone,
// independently of the SLAM system.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "dsm/io/dataset.h"

namespace dsm {

struct GtCheckOptions {
  int gap = 5;           // Frames between the two images of a pair.
  int stride = 3;        // Frames between the first images of consecutive pairs.
  int max_pairs = 100;   // Spread over the sequence.
  int corners = 300;     // Per pair (Shi-Tomasi).
  double min_baseline_m = 0.005;  // Pairs whose ground-truth camera moved less are skipped.
  void Validate() const;  // Throws InputError naming the bad option.
};

// Tracks of one frame pair, normalized coordinates (z = 1) of the undistorted rays.
struct PairTracks {
  size_t frame_a = 0, frame_b = 0;
  std::vector<Eigen::Vector2d> a, b;
};

// KLT tracks for the pairs chosen by `options` (all frames are candidates; pairs without ground
// truth are dropped later). Deterministic.
std::vector<PairTracks> TrackPairs(const Dataset& dataset, const GtCheckOptions& options);

struct EpipolarStats {
  size_t pairs = 0, tracks = 0;
  double median_px = 0.0, p90_px = 0.0;
};

// Sampson distances of the tracks under `ground_truth` (world_from_cam, stamps matched to the
// frames' within 1 ms), in pixels of focal length `focal_px`.
EpipolarStats EpipolarError(const std::vector<PairTracks>& tracks, const Dataset& dataset,
                            const Trajectory& ground_truth, const GtCheckOptions& options, double focal_px);

}  // namespace dsm

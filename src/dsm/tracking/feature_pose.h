// SPDX-License-Identifier: MIT
// A feature-based pose guess for relocalisation, where direct alignment has no basin wide enough:
// after a hand over the lens or a stretch of dark frames the camera may have moved by a third of
// the scene depth. ORB keypoints (oriented FAST, rotated BRIEF; OpenCV) of the frame are matched
// to a keyframe's (Hamming distance, Lowe's ratio test); a keyframe keypoint gets the inverse
// depth of the nearest map point within `max_depth_px` (the map is sparse but its points sit on
// the strong gradients corners are made of), X_k = pi^-1(u, rho); the pose follows from RANSAC
// PnP on the 3D-2D matches (calib3d), frame_from_keyframe. The caller refines it by direct
// alignment and judges it with the quality test: this is only a guess.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "dsm/geometry/camera.h"
#include "dsm/image/pyramid.h"
#include "dsm/lie/se3.h"
#include "dsm/tracking/frame_tracker.h"

namespace dsm {

struct FeaturePoseOptions {
  int max_features = 1000;
  double ratio = 0.8;            // Lowe's ratio test.
  float max_depth_px = 8.f;      // A keypoint takes the depth of the nearest map point this close.
  double ransac_px = 3.0;        // Reprojection error of a PnP inlier.
  int min_inliers = 20;
  double contrast = 40.0;        // Grey-level deviation the image is detected at (see feature_pose.cc).
};

struct OrbFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

// Keypoints and descriptors of level 0 of `pyramid`, or of a keyframe's fixed-point image
// (1/ImagePyramid::kValueScale grey levels).
OrbFeatures DetectOrbFeatures(const ImagePyramid& pyramid, const FeaturePoseOptions& options);
OrbFeatures DetectOrbFeatures(const Image<uint16_t>& fixed, const FeaturePoseOptions& options);

struct FeaturePose {
  bool ok = false;
  SE3d frame_from_keyframe;
  int matches = 0, inliers = 0;  // Matches with a depth, PnP inliers among them.
};

// Each of `frame`'s descriptors matched to its nearest in `keyframe`'s (queryIdx, trainIdx), kept
// when that is within options.ratio of the second nearest (Lowe's test); as OpenCV's brute-force
// k-nearest matcher would, the first of equally near descriptors taken.
std::vector<cv::DMatch> MatchFeatures(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                      const FeaturePoseOptions& options);

// The same pairs by OpenCV's brute-force k-nearest matcher (NORM_HAMMING, k = 2) and the ratio
// test: MatchFeatures' path for descriptors other than 256-bit ORB ones, and the reference its own
// loop is tested and timed against.
std::vector<cv::DMatch> MatchFeaturesBruteForce(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                                const FeaturePoseOptions& options);

// `points`: the keyframe's map points (level-0 pixel and inverse depth in the keyframe); `matches`:
// MatchFeatures(frame, keyframe, options), made by the caller when it has them already (their
// number ranks relocalisation candidates).
FeaturePose EstimateFeaturePose(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                const std::vector<cv::DMatch>& matches, const std::vector<ReferencePoint>& points,
                                const PinholeCamera& camera, const FeaturePoseOptions& options);
FeaturePose EstimateFeaturePose(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                const std::vector<ReferencePoint>& points, const PinholeCamera& camera,
                                const FeaturePoseOptions& options);

// Per keypoint of `features`: the inverse depth of the nearest of `points` (pixels and inverse
// depths in the same image) within options.max_depth_px, or 0 when none is that near.
std::vector<float> KeypointInverseDepths(const OrbFeatures& features, const std::vector<ReferencePoint>& points,
                                         const FeaturePoseOptions& options);

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/tracking/feature_pose.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

namespace dsm {

namespace {

// The image is detected on at a fixed contrast: I' = 128 + d (I - mean) / deviation. FAST's
// threshold is absolute (grey levels), so a dim or low-contrast view of a place finds few corners or
// none where a bright view of it finds hundreds, and the two could never be matched. BRIEF's
// comparisons of smoothed intensities do not change under a positive affine map, so the descriptors
// stay comparable; FAST's threshold becomes a share of the image's own contrast.
template <typename Value>
OrbFeatures Detect(int w, int h, const Value& value, const FeaturePoseOptions& options) {
  double sum = 0.0, sum2 = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = value(x, y);
      sum += v, sum2 += v * v;
    }
  const double n = static_cast<double>(w) * h;
  const double mean = sum / n, deviation = std::sqrt(std::max(sum2 / n - mean * mean, 0.0));
  OrbFeatures f;
  if (!(deviation > 0.0)) return f;  // A uniform image has no corners.
  const double gain = options.contrast / deviation;
  cv::Mat image(h, w, CV_8U);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      image.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(128.0 + gain * (value(x, y) - mean));
  cv::ORB::create(options.max_features)->detectAndCompute(image, cv::noArray(), f.keypoints, f.descriptors);
  return f;
}

}  // namespace

OrbFeatures DetectOrbFeatures(const ImagePyramid& pyramid, const FeaturePoseOptions& options) {
  return Detect(pyramid.width(0), pyramid.height(0), [&](int x, int y) { return pyramid.Value(0, x, y); }, options);
}

OrbFeatures DetectOrbFeatures(const Image<uint16_t>& fixed, const FeaturePoseOptions& options) {
  return Detect(fixed.width(), fixed.height(),
                [&](int x, int y) { return fixed(x, y) * (1.f / ImagePyramid::kValueScale); }, options);
}

namespace {

// The map points of a keyframe hashed by cells of `cell` pixels, for the nearest one to a keypoint.
class PointGrid {
 public:
  PointGrid(const std::vector<ReferencePoint>& points, float cell) : points_(points), cell_(cell) {
    for (size_t i = 0; i < points.size(); ++i) cells_[Key(Cell(points[i].pixel.x()), Cell(points[i].pixel.y()))].push_back(i);
  }
  // Index of the nearest point within `radius` (<= cell) of (x, y), or -1.
  int Nearest(float x, float y, float radius) const {
    int best = -1;
    float best_d2 = radius * radius;
    const int cx = Cell(x), cy = Cell(y);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = cells_.find(Key(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        for (size_t i : it->second) {
          const float d2 = (points_[i].pixel - Eigen::Vector2f(x, y)).squaredNorm();
          if (d2 <= best_d2) best_d2 = d2, best = static_cast<int>(i);
        }
      }
    return best;
  }

 private:
  int Cell(float v) const { return static_cast<int>(std::floor(v / cell_)); }
  static int64_t Key(int x, int y) { return (static_cast<int64_t>(x) << 32) ^ static_cast<uint32_t>(y); }
  const std::vector<ReferencePoint>& points_;
  float cell_;
  std::unordered_map<int64_t, std::vector<size_t>> cells_;
};

}  // namespace

namespace {

// Hamming distance of two 256-bit ORB descriptors.
inline int Hamming256(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int w = 0; w < 4; ++w) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * w, 8);
    std::memcpy(&y, b + 8 * w, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

// Each frame descriptor's nearest keyframe descriptor, kept when it is within `ratio` of the
// second nearest (Lowe's test); of equal distances the first keyframe descriptor is the nearest,
// as with OpenCV's brute-force k-nearest matcher, which this equals for ORB's 256-bit descriptors
// at a fourth of its time (a plain loop instead of a distance matrix and match lists).
__attribute__((always_inline)) inline void RatioMatches256(const cv::Mat& frame, const cv::Mat& keyframe,
                                                           double ratio, std::vector<cv::DMatch>* good) {
  for (int i = 0; i < frame.rows; ++i) {
    const uint8_t* q = frame.ptr<uint8_t>(i);
    int d1 = std::numeric_limits<int>::max(), d2 = d1, j1 = -1;
    for (int j = 0; j < keyframe.rows; ++j) {
      const int d = Hamming256(q, keyframe.ptr<uint8_t>(j));
      if (d < d1) {
        d2 = d1;
        d1 = d;
        j1 = j;
      } else if (d < d2) {
        d2 = d;
      }
    }
    if (d2 != std::numeric_limits<int>::max() && d1 <= ratio * d2) good->emplace_back(i, j1, static_cast<float>(d1));
  }
}

// The same loop compiled with the popcnt instruction (the build targets the x86-64 baseline),
// taken when the CPU has it. Dispatched by a check at the call, not by an ifunc resolver: those
// run before a sanitizer's runtime is up and crash ThreadSanitizer builds at load time.
__attribute__((target("popcnt"))) void RatioMatches256Popcnt(const cv::Mat& frame, const cv::Mat& keyframe,
                                                              double ratio, std::vector<cv::DMatch>* good) {
  RatioMatches256(frame, keyframe, ratio, good);
}

void RatioMatches256Generic(const cv::Mat& frame, const cv::Mat& keyframe, double ratio,
                            std::vector<cv::DMatch>* good) {
  RatioMatches256(frame, keyframe, ratio, good);
}

}  // namespace

std::vector<cv::DMatch> MatchFeatures(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                      const FeaturePoseOptions& options) {
  const cv::Mat& a = frame.descriptors;
  const cv::Mat& b = keyframe.descriptors;
  if (a.empty() || b.empty()) return {};
  if (a.type() != CV_8U || b.type() != CV_8U || a.cols != 32 || b.cols != 32)
    return MatchFeaturesBruteForce(frame, keyframe, options);
  static const bool popcnt = __builtin_cpu_supports("popcnt");
  std::vector<cv::DMatch> good;
  (popcnt ? RatioMatches256Popcnt : RatioMatches256Generic)(a, b, options.ratio, &good);
  return good;
}

std::vector<cv::DMatch> MatchFeaturesBruteForce(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                                const FeaturePoseOptions& options) {
  std::vector<cv::DMatch> good;
  if (frame.descriptors.empty() || keyframe.descriptors.empty()) return good;
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(frame.descriptors, keyframe.descriptors, knn, 2);
  for (const auto& m : knn)
    if (m.size() == 2 && m[0].distance <= options.ratio * m[1].distance) good.push_back(m[0]);
  return good;
}

std::vector<float> KeypointInverseDepths(const OrbFeatures& features, const std::vector<ReferencePoint>& points,
                                         const FeaturePoseOptions& options) {
  std::vector<float> idepths(features.keypoints.size(), 0.f);
  if (points.empty()) return idepths;
  const PointGrid grid(points, options.max_depth_px);
  for (size_t i = 0; i < idepths.size(); ++i) {
    const cv::Point2f& u = features.keypoints[i].pt;
    const int p = grid.Nearest(u.x, u.y, options.max_depth_px);
    if (p >= 0) idepths[i] = points[p].idepth;
  }
  return idepths;
}

FeaturePose EstimateFeaturePose(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                const std::vector<ReferencePoint>& points, const PinholeCamera& camera,
                                const FeaturePoseOptions& options) {
  if (points.empty()) return FeaturePose();
  return EstimateFeaturePose(frame, keyframe, MatchFeatures(frame, keyframe, options), points, camera, options);
}

FeaturePose EstimateFeaturePose(const OrbFeatures& frame, const OrbFeatures& keyframe,
                                const std::vector<cv::DMatch>& matches, const std::vector<ReferencePoint>& points,
                                const PinholeCamera& camera, const FeaturePoseOptions& options) {
  FeaturePose pose;
  if (points.empty()) return pose;
  const PointGrid grid(points, options.max_depth_px);
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  for (const cv::DMatch& m : matches) {
    const cv::Point2f& u = keyframe.keypoints[m.trainIdx].pt;
    const int p = grid.Nearest(u.x, u.y, options.max_depth_px);
    if (p < 0) continue;
    // X = pi^-1(u, rho): the keypoint's ray at the point's depth.
    const Eigen::Vector3d X = camera.Unproject(u.x, u.y) / points[p].idepth;
    object.emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z()));
    image.push_back(frame.keypoints[m.queryIdx].pt);
  }
  pose.matches = static_cast<int>(object.size());
  if (pose.matches < options.min_inliers) return pose;
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, 200, static_cast<float>(options.ransac_px),
                          0.999, inliers, cv::SOLVEPNP_EPNP)) {
    return pose;
  }
  pose.inliers = static_cast<int>(inliers.size());
  if (pose.inliers < options.min_inliers) return pose;
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Re(r, c) = R(r, c);
  pose.frame_from_keyframe = SE3d(Eigen::Quaterniond(Re).normalized(), Eigen::Vector3d(tvec[0], tvec[1], tvec[2]));
  pose.ok = pose.frame_from_keyframe.Matrix().allFinite();
  return pose;
}

}  // namespace dsm

// SPDX-License-Identifier: MIT
#include "dsm/tracking/initializer.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "dsm/util/check.h"
#include "dsm/util/median.h"

namespace dsm {

void InitializerOptions::Validate() const {
  if (!(min_parallax_deg > 0)) throw InputError("initializer.min_parallax_deg must be positive");
  if (!(min_track_share >= 0 && min_track_share < 1)) throw InputError("initializer.min_track_share must be in [0, 1)");
}

namespace {

Image<uint8_t> ToGray8(const Image<float>& f) {
  Image<uint8_t> g(f.width(), f.height());
  for (size_t i = 0; i < f.size(); ++i) g.data()[i] = static_cast<uint8_t>(std::clamp(std::lround(f.data()[i]), 0L, 255L));
  return g;
}

cv::Mat Wrap(const Image<uint8_t>& img) {
  return cv::Mat(img.height(), img.width(), CV_8UC1, const_cast<uint8_t*>(img.data()));
}

}  // namespace

Initializer::Initializer(const InitializerOptions& options) : options_(options) { options_.Validate(); }

void Initializer::SetReference(const Image<float>& image, const PinholeCamera& camera) {
  camera_ = camera;
  reference_ = ToGray8(image);
  previous_ = reference_;
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(Wrap(reference_), corners, options_.max_corners, 0.005, 8.0);
  reference_corners_.clear();
  for (const auto& c : corners) reference_corners_.emplace_back(c.x, c.y);
  current_corners_ = reference_corners_;
  alive_.assign(reference_corners_.size(), true);
  has_reference_ = true;
  plane_normals_.clear();
}

int Initializer::NumTracks() const { return static_cast<int>(std::count(alive_.begin(), alive_.end(), true)); }

double Initializer::TrackShare() const {
  return alive_.empty() ? 0.0 : static_cast<double>(NumTracks()) / static_cast<double>(alive_.size());
}

void Initializer::TrackCorners(const Image<uint8_t>& gray) {
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<cv::Point2f> prev_pts, next_pts;
  std::vector<int> ids;
  for (size_t i = 0; i < alive_.size(); ++i) {
    if (!alive_[i]) continue;
    prev_pts.emplace_back(current_corners_[i].x(), current_corners_[i].y());
    ids.push_back(static_cast<int>(i));
  }
  if (prev_pts.empty()) return;
  std::vector<uchar> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(Wrap(previous_), Wrap(gray), prev_pts, next_pts, status, error, cv::Size(21, 21), 3, stop);
  // Forward-backward check removes drifting tracks.
  std::vector<cv::Point2f> back_pts;
  std::vector<uchar> back_status;
  cv::calcOpticalFlowPyrLK(Wrap(gray), Wrap(previous_), next_pts, back_pts, back_status, error, cv::Size(21, 21), 3, stop);
  const auto inside = [&](const cv::Point2f& p) { return p.x >= 0 && p.y >= 0 && p.x < gray.width() - 1 && p.y < gray.height() - 1; };
  for (size_t k = 0; k < ids.size(); ++k) {
    const bool consistent = back_status[k] && std::hypot(back_pts[k].x - prev_pts[k].x, back_pts[k].y - prev_pts[k].y) < 1.0;
    if (!status[k] || !inside(next_pts[k]) || !consistent) {
      alive_[ids[k]] = false;
      continue;
    }
    current_corners_[ids[k]] = Eigen::Vector2f(next_pts[k].x, next_pts[k].y);
  }
}

InitResult Initializer::AddFrame(const Image<float>& image) {
  DSM_CHECK(has_reference_, "initializer needs a reference frame");
  InitResult result;
  const Image<uint8_t> gray = ToGray8(image);
  TrackCorners(gray);
  previous_ = gray;
  plane_normals_.emplace_back();

  std::vector<cv::Point2f> ref, cur;
  std::vector<int> track_ids;
  for (size_t i = 0; i < alive_.size(); ++i) {
    if (!alive_[i]) continue;
    ref.emplace_back(reference_corners_[i].x(), reference_corners_[i].y());
    cur.emplace_back(current_corners_[i].x(), current_corners_[i].y());
    track_ids.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(ref.size()) < options_.min_inliers) {
    result.reason = "too few tracks (" + std::to_string(ref.size()) + ")";
    return result;
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  cv::Mat e_mask, h_mask;
  const cv::Mat E = cv::findEssentialMat(ref, cur, K, cv::RANSAC, 0.999, options_.ransac_threshold_px, e_mask);
  if (E.rows != 3 || E.cols != 3) {
    result.reason = "no essential matrix";
    return result;
  }
  cv::Mat R, t, pose_mask = e_mask.clone();
  const int in_front = cv::recoverPose(E, ref, cur, K, R, t, pose_mask);
  const cv::Mat H = cv::findHomography(ref, cur, cv::RANSAC, 2.0 * options_.ransac_threshold_px, h_mask);
  const int e_inliers = cv::countNonZero(e_mask);
  const int h_inliers = H.empty() ? 0 : cv::countNonZero(h_mask);
  result.homography_ratio = e_inliers > 0 ? static_cast<double>(h_inliers) / e_inliers : 1.0;
  const bool explained = result.homography_ratio > options_.max_homography_ratio;
  const bool plane_fills_view = result.homography_ratio >= options_.planar_min_homography_ratio;
  const bool planar = options_.planar_start && !H.empty() && PlanarStart(H, ref, h_mask, plane_fills_view, &result);
  if (planar || explained) {
    if (!planar)
      result.reason = "a homography explains the motion (ratio " + std::to_string(result.homography_ratio) + ")";
    return result;
  }
  if (in_front < options_.min_inliers) {
    result.reason = "too few essential-matrix inliers in front of the cameras (" + std::to_string(in_front) + ")";
    return result;
  }
  // Triangulate the inliers (reference = identity) and measure the parallax.
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  for (int r = 0; r < 3; ++r) {
    te(r) = t.at<double>(r);
    for (int c = 0; c < 3; ++c) Re(r, c) = R.at<double>(r, c);
  }
  const SE3d cur_from_ref(SO3d(Re), te);  // |t| = 1
  result.current_from_reference = cur_from_ref;
  std::vector<double> parallax, depth;
  std::vector<InitPoint> points;
  const Eigen::Vector3d centre_cur = cur_from_ref.Inverse().Translation();
  for (size_t k = 0; k < ref.size(); ++k) {
    if (!pose_mask.at<uchar>(static_cast<int>(k))) continue;
    const Eigen::Vector3d d0 = camera_.Unproject(ref[k].x, ref[k].y).normalized();
    const Eigen::Vector3d d1 = (Re.transpose() * camera_.Unproject(cur[k].x, cur[k].y)).normalized();  // in ref frame
    // Midpoint triangulation: rays c0 + s d0 and c1 + u d1.
    const Eigen::Vector3d c1 = centre_cur;
    const double b = d0.dot(d1);
    const double denom = 1.0 - b * b;
    if (denom < 1e-12) continue;
    const Eigen::Vector3d w = -c1;  // c0 - c1
    const double s = (b * d1.dot(w) - d0.dot(w)) / denom;
    const double u = (d1.dot(w) - b * d0.dot(w)) / denom;
    if (s <= 0 || u <= 0) continue;
    const Eigen::Vector3d p = 0.5 * (s * d0 + c1 + u * d1);
    if (p.z() <= 0) continue;
    parallax.push_back(std::acos(std::clamp(b, -1.0, 1.0)) * 180.0 / M_PI);
    depth.push_back(p.z());
    points.push_back({Eigen::Vector2f(ref[k].x, ref[k].y), static_cast<float>(1.0 / p.z())});
  }
  if (static_cast<int>(points.size()) < options_.min_inliers) {
    result.reason = "too few triangulated points (" + std::to_string(points.size()) + ")";
    return result;
  }
  result.parallax_deg = Median(parallax);

  if (result.parallax_deg < options_.min_parallax_deg) {
    result.reason = "too little parallax (" + std::to_string(result.parallax_deg) + " deg)";
    return result;
  }
  // Scale: median depth 1.
  const double scale = 1.0 / Median(depth);
  for (InitPoint& p : points) p.idepth = static_cast<float>(p.idepth / scale);
  result.current_from_reference = SE3d(cur_from_ref.So3(), cur_from_ref.Translation() * scale);
  result.points = std::move(points);
  result.ok = true;
  return result;
}

bool Initializer::PlanarStart(const cv::Mat& H, const std::vector<cv::Point2f>& ref, const cv::Mat& h_mask, bool accept,
                              InitResult* result) {
  const cv::Mat K = (cv::Mat_<double>(3, 3) << camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  std::vector<cv::Mat> rotations, translations, normals;
  cv::decomposeHomographyMat(H, K, rotations, translations, normals);
  std::vector<Eigen::Vector3d> rays;  // Of the inlier tracks in the reference, z = 1.
  std::vector<Eigen::Vector2f> pixels;
  for (size_t k = 0; k < ref.size(); ++k) {
    if (!h_mask.at<uchar>(static_cast<int>(k))) continue;
    rays.push_back(camera_.Unproject(ref[k].x, ref[k].y));
    pixels.emplace_back(ref[k].x, ref[k].y);
  }
  if (static_cast<int>(rays.size()) < options_.min_inliers) return false;
  struct Solution {
    Eigen::Matrix3d R;
    Eigen::Vector3d t, n;  // t = translation / d.
  };
  std::vector<Solution> valid;
  for (size_t i = 0; i < rotations.size(); ++i) {
    Solution s;
    for (int r = 0; r < 3; ++r) {
      s.t(r) = translations[i].at<double>(r);
      s.n(r) = normals[i].at<double>(r);
      for (int c = 0; c < 3; ++c) s.R(r, c) = rotations[i].at<double>(r, c);
    }
    // In front of both cameras: depth 1 / (n^T x) > 0 in the reference and in the current frame.
    int in_front = 0;
    for (const Eigen::Vector3d& x : rays) {
      const double nx = s.n.dot(x);
      in_front += nx > 0 && (s.R * (x / nx) + s.t).z() > 0;
    }
    if (in_front >= 0.9 * rays.size()) valid.push_back(s);
  }
  for (const Solution& s : valid) plane_normals_.back().push_back(s.n);
  if (!accept || valid.size() != 2) return false;
  const double parallax = std::max(valid[0].t.norm(), valid[1].t.norm());
  result->parallax_deg = std::atan(parallax) * 180.0 / M_PI;
  if (result->parallax_deg < options_.min_parallax_deg) return false;
  // The solution whose normal some frame at least planar_frame_gap back agrees with, and not its twin.
  const double tolerance = options_.planar_normal_tolerance_deg * M_PI / 180.0;
  const auto nearest = [](const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& others) {
    double best = M_PI;
    for (const Eigen::Vector3d& o : others) best = std::min(best, std::acos(std::clamp(n.dot(o), -1.0, 1.0)));
    return best;
  };
  int chosen = -1;
  const int frames = static_cast<int>(plane_normals_.size());
  for (int g = 0; g + options_.planar_frame_gap < frames && chosen < 0; ++g) {
    const std::vector<Eigen::Vector3d>& earlier = plane_normals_[g];
    if (earlier.size() != 2) continue;
    for (int i = 0; i < 2; ++i)
      if (nearest(valid[i].n, earlier) < tolerance && nearest(valid[1 - i].n, earlier) > 3.0 * tolerance) chosen = i;
  }
  if (chosen < 0) {
    result->reason = "a plane, its two solutions not told apart yet";
    return false;
  }
  const Solution& s = valid[chosen];
  // Depths on the plane (d = 1), then median depth 1.
  std::vector<double> depth;
  std::vector<InitPoint> points;
  for (size_t k = 0; k < rays.size(); ++k) {
    const double nx = s.n.dot(rays[k]);
    if (nx <= 0) continue;
    depth.push_back(1.0 / nx);
    points.push_back({pixels[k], static_cast<float>(nx)});
  }
  const double median = Median(depth);
  for (InitPoint& p : points) p.idepth = static_cast<float>(p.idepth * median);
  result->current_from_reference = SE3d(SO3d(s.R), s.t / median);
  result->points = std::move(points);
  result->planar = true;
  result->ok = true;
  return true;
}

}  // namespace dsm

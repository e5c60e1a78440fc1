// SPDX-License-Identifier: MIT
#include "dsm/calibration/calibrate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "dsm/calibration/detect.h"
#include "dsm/calibration/refine.h"
#include "dsm/io/image_store.h"
#include "dsm/io/mat_gray.h"
#include "dsm/io/video_dataset.h"
#include "dsm/lie/se3.h"
#include "dsm/util/check.h"
#include "dsm/util/median.h"
#include "dsm/util/nelder_mead.h"

namespace dsm {

namespace fs = std::filesystem;

namespace {

constexpr double kMaxEdgeWidthPx = 3.0;  // Sharpness: the median width of the board's edges.
// A corner is an outlier beyond 5 times the median corner's error, and never within this.
constexpr double kMinCornerOutlierPx = 0.25;

// The frames of `input`: a folder of images (its images/ when it has one) or a video file.
std::shared_ptr<ImageStore> FramesOf(const fs::path& input) {
  if (fs::is_directory(input)) return MakeFolderStore(fs::is_directory(input / "images") ? input / "images" : input);
  if (!fs::exists(input)) throw InputError(input.string() + ": no such file or folder");
  return OpenVideoFrames(input);
}

// Farthest-point sampling of the views' places, from the sharpest.
std::vector<int> PickViews(const std::vector<BoardDetection>& found, int max_views) {
  std::vector<int> picked;
  std::vector<double> distance(found.size(), INFINITY);
  int next = static_cast<int>(std::min_element(found.begin(), found.end(), [](const auto& a, const auto& b) {
                                return a.edge_width < b.edge_width;
                              }) - found.begin());
  while (static_cast<int>(picked.size()) < std::min<int>(max_views, found.size())) {
    picked.push_back(next);
    double best = -1.0;
    for (size_t i = 0; i < found.size(); ++i) {
      double d = 0.0;
      for (int k = 0; k < 5; ++k) d += std::pow(found[i].place[k] - found[next].place[k], 2);
      distance[i] = std::min(distance[i], d);
    }
    for (size_t i = 0; i < found.size(); ++i)
      if (distance[i] > best) best = distance[i], next = static_cast<int>(i);
    if (best <= 0.0) break;  // Every view left is one of those picked.
  }
  std::sort(picked.begin(), picked.end());
  return picked;
}

struct Solution {
  CameraCalibration camera;
  std::vector<SE3d> cam_from_board;
  std::vector<double> deviations;  // RefinedCalibration::deviations.
};

// OpenCV's calibration, the initial solution: calibrateCamera (pinhole, radtan: k3 held at 0) or
// fisheye::calibrate (equidistant).
Solution OpenCvSolution(const std::vector<BoardDetection>& views, const BoardSpec& board, CameraModel model, cv::Size size) {
  const std::vector<Eigen::Vector3d> all = board.Corners();
  std::vector<std::vector<cv::Point3f>> object(views.size());
  for (size_t v = 0; v < views.size(); ++v)
    for (int id : views[v].ids) object[v].emplace_back(all[id].x(), all[id].y(), all[id].z());
  Solution s;
  s.camera.model = model;
  s.camera.width = size.width;
  s.camera.height = size.height;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat K, D;
  try {
    if (model == CameraModel::kEquidistant) {
      std::vector<std::vector<cv::Point3d>> obj(views.size());
      std::vector<std::vector<cv::Point2d>> img(views.size());
      for (size_t v = 0; v < views.size(); ++v) {
        for (const cv::Point3f& p : object[v]) obj[v].emplace_back(p);
        for (const cv::Point2f& p : views[v].corners) img[v].emplace_back(p);
      }
      cv::fisheye::calibrate(obj, img, size, K, D, rvecs, tvecs,
                             cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
    } else {
            std::vector<std::vector<cv::Point2f>> img;
      for (const BoardDetection& d : views) img.push_back(d.corners);
      int flags = cv::CALIB_FIX_K3;
      if (model == CameraModel::kPinhole) flags |= cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_ZERO_TANGENT_DIST;
      cv::calibrateCamera(object, img, size, K, D, rvecs, tvecs, flags,
                          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
    }
  } catch (const cv::Exception& e) {
    throw InputError(std::string("calibration failed: the views do not constrain the camera (") + e.what() + ")");
  }
  s.camera.fx = K.at<double>(0, 0);
  s.camera.fy = K.at<double>(1, 1);
  s.camera.cx = K.at<double>(0, 2);
  s.camera.cy = K.at<double>(1, 2);
  const int n = model == CameraModel::kPinhole ? 0 : 4;
  for (int i = 0; i < n; ++i) s.camera.distortion.push_back(D.at<double>(i));
  // OpenCV's rotation vectors are SO(3)'s tangent.
  const auto vec3 = [](const cv::Mat& m) { return Eigen::Vector3d(m.at<double>(0), m.at<double>(1), m.at<double>(2)); };
  for (size_t v = 0; v < views.size(); ++v) s.cam_from_board.emplace_back(SO3d::Exp(vec3(rvecs[v])), vec3(tvecs[v]));
  return s;
}

// The FOV camera closest to an equidistant one: the same fx fy cx cy, and the w whose radial
// mapping atan(2 r tan(w / 2)) / w best matches the equidistant theta_d(r) out to the image's
// corners (the start of the refinement).
CameraCalibration FovFrom(const CameraCalibration& equidistant) {
  double r_max = 0.0;
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(equidistant.width - 1, 0),
                                       Eigen::Vector2d(0, equidistant.height - 1),
                                       Eigen::Vector2d(equidistant.width - 1, equidistant.height - 1)}) {
    Eigen::Vector2d n;
    if (equidistant.Unproject(corner, &n)) r_max = std::max(r_max, n.norm());
  }
  if (r_max <= 0.0) r_max = 1.0;
  CameraCalibration fov = equidistant;
  fov.model = CameraModel::kFov;
  const auto misfit = [&](const Eigen::VectorXd& w) {
    if (!(std::abs(w[0]) > 1e-6)) return double(INFINITY);  // w and -w map alike; 0 is no model.
    fov.distortion = {w[0]};
    double sum = 0.0;
    for (int i = 1; i <= 50; ++i) {
      const Eigen::Vector2d xy(r_max * i / 50.0, 0.0);
      sum += (fov.Distort(xy) - equidistant.Distort(xy)).squaredNorm();
    }
    return sum;
  };
  NelderMeadOptions search;
  search.tolerance = 1e-15;
  fov.distortion = {std::abs(NelderMead(misfit, Eigen::VectorXd::Constant(1, 1.0), search).x[0])};
  return fov;
}

// OpenCV's solution (FOV: from the equidistant one), refined with dsm's own camera model.
Solution Solve(const std::vector<BoardDetection>& views, const BoardSpec& board, CameraModel model, cv::Size size) {
  Solution s = OpenCvSolution(views, board, model == CameraModel::kFov ? CameraModel::kEquidistant : model, size);
  if (model == CameraModel::kFov) s.camera = FovFrom(s.camera);
  const std::vector<Eigen::Vector3d> all = board.Corners();
  std::vector<CornerView> corners(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    for (int id : views[v].ids) corners[v].board.push_back(all[id]);
    for (const cv::Point2f& p : views[v].corners) corners[v].image.emplace_back(p.x, p.y);
  }
  const RefinedCalibration refined = RefineCalibration(s.camera, s.cam_from_board, corners);
  s.camera = refined.camera;
  s.cam_from_board = refined.cam_from_board;
  s.deviations = refined.deviations;
  return s;
}

// Each corner's reprojection error, view by view, with the model as dsm projects it.
std::vector<std::vector<double>> CornerResiduals(const Solution& s, const std::vector<BoardDetection>& views,
                                                 const BoardSpec& board) {
  const std::vector<Eigen::Vector3d> corners = board.Corners();
  std::vector<std::vector<double>> residuals(views.size());
  for (size_t v = 0; v < views.size(); ++v)
    for (size_t i = 0; i < views[v].ids.size(); ++i) {
      const Eigen::Vector2d px = s.camera.Project(s.cam_from_board[v] * corners[views[v].ids[i]]);
      residuals[v].push_back((px - Eigen::Vector2d(views[v].corners[i].x, views[v].corners[i].y)).norm());
    }
  return residuals;
}

// Reprojection RMS of each view's corners.
std::vector<double> ViewRms(const Solution& s, const std::vector<BoardDetection>& views, const BoardSpec& board) {
  std::vector<double> rms;
  for (const std::vector<double>& r : CornerResiduals(s, views, board)) {
    double sum = 0.0;
    for (double e : r) sum += e * e;
    rms.push_back(r.empty() ? 0.0 : std::sqrt(sum / r.size()));
  }
  return rms;
}

}  // namespace

CalibrationResult Calibrate(const fs::path& input, const CalibrationOptions& options) {
  const BoardSpec& board = options.board;
  std::vector<BoardDetection> found;
  CalibrationResult out;
  const std::shared_ptr<ImageStore> frames = FramesOf(input);
  const std::vector<std::string> names = frames->List();
  if (names.empty()) throw InputError(frames->Describe() + ": no image files (png, jpg, pgm, bmp, tiff)");
  out.frames = static_cast<int>(names.size());
  std::optional<cv::Size> size;
  for (size_t i = 0; i < names.size(); ++i) {
    const Image<uint8_t> image = frames->Load(names[i]);
    const cv::Mat grey = Gray8View(image);
    if (!size) size = grey.size();
    if (grey.size() != *size)
      throw InputError(input.string() + ": frame " + std::to_string(i) + " is " + std::to_string(grey.cols) + "x" +
                       std::to_string(grey.rows) + ", the first was " + std::to_string(size->width) + "x" +
                       std::to_string(size->height));
    std::optional<BoardDetection> d = DetectBoard(grey, board);
    if (!d) continue;
    d->frame = static_cast<int>(i);
    found.push_back(std::move(*d));
  }
  if (found.empty())
    throw InputError(input.string() + ": the board " + board.ToString() + " is in none of the " +
                     std::to_string(out.frames) + " frames (its inner corners: COLSxROWS)");
  std::vector<BoardDetection> sharp;
  for (const BoardDetection& d : found) {
    CalibrationView v;
    v.frame = d.frame;
    v.corners = static_cast<int>(d.ids.size());
    if (d.edge_width > kMaxEdgeWidthPx) {
      v.why_not = "blurred";
    } else {
      sharp.push_back(d);
    }
    out.views.push_back(v);
  }
  std::vector<BoardDetection> used;
  for (int k : PickViews(sharp, options.max_views)) used.push_back(sharp[k]);
  if (static_cast<int>(used.size()) < kMinViews)
    throw InputError(input.string() + ": the board is sharp in " + std::to_string(used.size()) + " frames; " +
                     std::to_string(kMinViews) + " or more views are needed, at different places and tilts");
  Solution s = Solve(used, board, options.model, *size);
  // Outliers: corners far from where the solution projects them (a ChArUco corner the markers'
  // interpolation misplaced by a pixel or two), then views whose RMS is far above the others'.
  // Calibrated again without them, once.
  std::map<int, int> corners_dropped;  // By frame.
  std::vector<BoardDetection> trimmed = used;
  {
    const std::vector<std::vector<double>> residuals = CornerResiduals(s, used, board);
    std::vector<double> all;
    for (const auto& r : residuals) all.insert(all.end(), r.begin(), r.end());
    const double corner_limit = std::max(kMinCornerOutlierPx, 5.0 * Median(all));
    for (size_t v = 0; v < used.size(); ++v) {
      BoardDetection& t = trimmed[v];
      t.ids.clear();
      t.corners.clear();
      for (size_t i = 0; i < used[v].ids.size(); ++i)
        if (residuals[v][i] <= corner_limit) t.ids.push_back(used[v].ids[i]), t.corners.push_back(used[v].corners[i]);
      if (t.ids.size() < used[v].ids.size())
        corners_dropped[used[v].frame] = static_cast<int>(used[v].ids.size() - t.ids.size());
    }
  }
  std::vector<double> rms = ViewRms(s, trimmed, board);
  const double limit = std::max(0.5, 3.0 * Median(rms));
  std::vector<BoardDetection> kept;
  std::vector<int> dropped;
  for (size_t v = 0; v < trimmed.size(); ++v) {
    const bool enough_corners = static_cast<int>(trimmed[v].ids.size()) >= kMinCorners;
    (enough_corners && rms[v] <= limit ? kept.push_back(trimmed[v]) : dropped.push_back(trimmed[v].frame));
  }
  if ((!dropped.empty() || !corners_dropped.empty()) && static_cast<int>(kept.size()) >= kMinViews) {
    used = std::move(kept);
    s = Solve(used, board, options.model, *size);
  } else {
    // Too few views would be left: the first solution stands, with every view and corner.
    dropped.clear();
    corners_dropped.clear();
  }
  rms = ViewRms(s, used, board);
  // The verdicts per view, and the RMS over every corner used.
  double sum = 0.0;
  int corners = 0;
  for (CalibrationView& v : out.views) {
    if (!v.why_not.empty()) continue;
    const auto it = std::find_if(used.begin(), used.end(), [&](const BoardDetection& d) { return d.frame == v.frame; });
    if (it == used.end()) {
      v.why_not = std::count(dropped.begin(), dropped.end(), v.frame) ? "outlier" : "like another view";
      continue;
    }
    v.used = true;
    v.rms_px = rms[it - used.begin()];
    if (const auto c = corners_dropped.find(v.frame); c != corners_dropped.end()) v.corners_dropped = c->second;
    sum += v.rms_px * v.rms_px * it->ids.size();
    corners += static_cast<int>(it->ids.size());
  }
  out.camera = s.camera;
  out.views_used = static_cast<int>(used.size());
  out.rms_px = std::sqrt(sum / corners);
  // Coverage: the 3x3 cells no corner fell in.
  static const char* kCells[3][3] = {{"top-left", "top", "top-right"},
                                     {"left", "centre", "right"},
                                     {"bottom-left", "bottom", "bottom-right"}};
  bool covered[3][3] = {};
  for (const BoardDetection& d : used)
    for (const cv::Point2f& p : d.corners)
      covered[std::clamp(int(3 * p.y / size->height), 0, 2)][std::clamp(int(3 * p.x / size->width), 0, 2)] = true;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!covered[r][c]) out.uncovered.push_back(kCells[r][c]);
  if (!s.deviations.empty()) {
    const char* parameters[4] = {"fx", "fy", "cx", "cy"};
    const double values[4] = {s.camera.fx, s.camera.fy, s.camera.cx, s.camera.cy};
    for (int i = 0; i < 4; ++i) {
      const bool weak = i < 2 ? s.deviations[i] > 0.005 * values[i] : s.deviations[i] > 5.0;
      if (!weak) continue;
      char line[96];
      std::snprintf(line, sizeof(line), "%s %.2f +- %.2f px", parameters[i], values[i], s.deviations[i]);
      out.weak.push_back(line);
    }
    if (s.deviations[0] > 0.05 * s.camera.fx)
      throw InputError(input.string() + ": the views leave the focal length unconstrained (fx " +
                       std::to_string(s.camera.fx) + " +- " + std::to_string(s.deviations[0]) +
                       " px): tilt the board towards and away from the camera");
  }
  return out;
}

}  // namespace dsm

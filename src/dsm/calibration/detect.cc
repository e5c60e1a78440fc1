// SPDX-License-Identifier: MIT
#include "dsm/calibration/detect.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "dsm/calibration/charuco.h"
#include "dsm/calibration/corner_symmetry.h"
#include "dsm/util/median.h"

namespace dsm {

namespace {

// The smallest distance between neighbouring corners found (pixels).
double Spacing(const BoardDetection& d, const BoardSpec& board) {
  double spacing = INFINITY;
  const int cols = board.CornerCols();
  for (size_t a = 0; a < d.ids.size(); ++a)
    for (size_t b = a + 1; b < d.ids.size(); ++b) {
      const int da = d.ids[a], db = d.ids[b];
      const bool row_neighbours = db == da + 1 && db % cols != 0;
      if (row_neighbours || db == da + cols) spacing = std::min<double>(spacing, cv::norm(d.corners[b] - d.corners[a]));
    }
  return spacing;
}

// The grid of every inner corner in the image: those found, and the others where the homography
// of those found puts them.
std::vector<cv::Point2f> WholeGrid(const BoardDetection& d, const BoardSpec& board) {
  if (static_cast<int>(d.ids.size()) == board.NumCorners()) return d.corners;
  const std::vector<Eigen::Vector3d> all = board.Corners();
  std::vector<cv::Point2f> plane, grid;
  for (int id : d.ids) plane.emplace_back(all[id].x(), all[id].y());
  const cv::Mat H = cv::findHomography(plane, d.corners);
  std::vector<cv::Point2f> on_board;
  for (const Eigen::Vector3d& p : all) on_board.emplace_back(p.x(), p.y());
  if (H.empty()) return d.corners;
  cv::perspectiveTransform(on_board, grid, H);
  return grid;
}

std::array<double, 5> Place(const std::vector<cv::Point2f>& c, const BoardSpec& b, cv::Size size) {
  cv::Point2f mean(0, 0);
  for (const cv::Point2f& p : c) mean += p;
  mean *= 1.0f / c.size();
  const cv::Rect box = cv::boundingRect(c);
  const auto len = [&](int a, int z) { return std::hypot(c[z].x - c[a].x, c[z].y - c[a].y); };
  const int cols = b.CornerCols(), last_row = (b.CornerRows() - 1) * cols;
  const double top = len(0, cols - 1), bottom = len(last_row, last_row + cols - 1);
  const double left = len(0, last_row), right = len(cols - 1, last_row + cols - 1);
  return {mean.x / size.width, mean.y / size.height, std::sqrt(box.area() / double(size.area())),
          std::log(top / bottom), std::log(left / right)};
}

// cornerSubPix where the image's gradients are orthogonal to the rays from the corner, then the
// corner's point symmetry (corner_symmetry.h), in a window a third of the corners' spacing, and
// short of a ChArUco board's markers (a radius of 2 to 8 px).
void RefineCorners(const cv::Mat& grey, const BoardSpec& board, BoardDetection* d) {
  const double spacing = Spacing(*d, board);
  const double reach = std::min(spacing / 3.0, 0.9 * board.MarkerMargin() * spacing);
  const int half = std::clamp(static_cast<int>(reach), 2, 8);
  cv::cornerSubPix(grey, d->corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-4));
  RefineBySymmetry(grey, half, &d->corners);
}

float Bilinear(const cv::Mat& grey, cv::Point2f p) {
  const int x = static_cast<int>(std::floor(p.x)), y = static_cast<int>(std::floor(p.y));
  if (x < 0 || y < 0 || x + 1 >= grey.cols || y + 1 >= grey.rows) return NAN;
  const float fx = p.x - x, fy = p.y - y;
  const auto at = [&](int u, int v) { return static_cast<float>(grey.at<uint8_t>(v, u)); };
  return (1 - fy) * ((1 - fx) * at(x, y) + fx * at(x + 1, y)) + fy * ((1 - fx) * at(x, y + 1) + fx * at(x + 1, y + 1));
}

// The median width of the edges between neighbouring corners found: across each edge at its
// middle, over the white margin around a marker (the profile stays off the marker itself).
double ChArUcoEdgeWidth(const cv::Mat& grey, const BoardDetection& d, const BoardSpec& board) {
  const int cols = board.CornerCols();
  std::vector<double> widths;
  for (size_t a = 0; a < d.ids.size(); ++a)
    for (size_t b = 0; b < d.ids.size(); ++b) {
      const int da = d.ids[a], db = d.ids[b];
      if (!((db == da + 1 && db % cols != 0) || db == da + cols)) continue;
      const cv::Point2f along = d.corners[b] - d.corners[a];
      const float length = static_cast<float>(cv::norm(along));
      if (length < 6.0f) continue;
      const cv::Point2f middle = 0.5f * (d.corners[a] + d.corners[b]), normal(-along.y / length, along.x / length);
      const float reach = std::max(2.0f, 0.9f * static_cast<float>(board.MarkerMargin()) * length);
      constexpr float kStep = 0.25f;
      std::vector<float> profile;
      for (float t = -reach; t <= reach + 1e-3f; t += kStep) profile.push_back(Bilinear(grey, middle + t * normal));
      if (std::any_of(profile.begin(), profile.end(), [](float v) { return std::isnan(v); })) continue;
      const int n = static_cast<int>(profile.size()), quarter = n / 4, per_px = static_cast<int>(1.0f / kStep);
      float low = 0, high = 0, gradient = 0;
      for (int i = 0; i < quarter; ++i) low += profile[i] / quarter, high += profile[n - 1 - i] / quarter;
      for (int i = 0; i + per_px < n; ++i) gradient = std::max(gradient, std::abs(profile[i + per_px] - profile[i]));
      if (gradient > 0.0f) widths.push_back(std::abs(high - low) / gradient);
    }
  return widths.empty() ? INFINITY : Median(widths);
}

std::optional<BoardDetection> DetectCheckerboard(const cv::Mat& grey, const BoardSpec& board) {
  const cv::Size pattern(board.cols, board.rows);
  BoardDetection d;
  if (!cv::findChessboardCornersSB(grey, pattern, d.corners, cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY))
    return std::nullopt;
  for (int i = 0; i < board.NumCorners(); ++i) d.ids.push_back(i);
  RefineCorners(grey, board, &d);
  d.edge_width = cv::estimateChessboardSharpness(grey, pattern, d.corners)[0];
  return d;
}

std::optional<BoardDetection> DetectCharuco(const cv::Mat& grey, const BoardSpec& board) {
  const cv::Ptr<cv::aruco::CharucoBoard> charuco = CharucoBoardOf(board);
  std::vector<std::vector<cv::Point2f>> markers;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(grey, charuco->dictionary, markers, marker_ids);
  if (marker_ids.size() < 2) return std::nullopt;
  BoardDetection d;
  cv::aruco::interpolateCornersCharuco(markers, marker_ids, grey, charuco, d.corners, d.ids);
  if (static_cast<int>(d.ids.size()) < kMinCorners) return std::nullopt;
  // Not all on one line: the corners' spread on the board, its smaller axis over 0.4 squares.
  const std::vector<Eigen::Vector3d> all = board.Corners();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int id : d.ids) mean += all[id].head<2>() / d.ids.size();
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (int id : d.ids) spread += (all[id].head<2>() - mean) * (all[id].head<2>() - mean).transpose() / d.ids.size();
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(spread).eigenvalues()[0] < std::pow(0.4 * board.square_m, 2))
    return std::nullopt;
  // In the order BoardSpec::Corners lists them.
  std::vector<int> order(d.ids.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d.ids[a] < d.ids[b]; });
  BoardDetection sorted;
  for (int i : order) sorted.ids.push_back(d.ids[i]), sorted.corners.push_back(d.corners[i]);
  RefineCorners(grey, board, &sorted);
  sorted.edge_width = ChArUcoEdgeWidth(grey, sorted, board);
  return sorted;
}

}  // namespace

std::optional<BoardDetection> DetectBoard(const cv::Mat& grey, const BoardSpec& board) {
  std::optional<BoardDetection> d =
      board.kind == BoardKind::kCharuco ? DetectCharuco(grey, board) : DetectCheckerboard(grey, board);
  if (d) d->place = Place(WholeGrid(*d, board), board, grey.size());
  return d;
}

}  // namespace dsm

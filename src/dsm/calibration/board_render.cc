// SPDX-License-Identifier: MIT
#include "dsm/calibration/board_render.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/core.hpp>
#include <tbb/parallel_for.h>

#include "dsm/calibration/charuco.h"
#include "dsm/io/calibration_io.h"
#include "dsm/io/dataset.h"
#include "dsm/io/folder_dataset.h"
#include "dsm/io/image_io.h"
#include "dsm/synth/renderer.h"
#include "dsm/synth/scenes.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

// Rays per pixel along each axis: a pixel whose kCoarse x kCoarse rays all see one colour takes
// it; a pixel an edge crosses averages kFine x kFine (its value then places the edge within about
// 1 / kFine^2 of a pixel's area).
constexpr int kCoarse = 4, kFine = 16;
constexpr double kBlack = 40.0, kWhite = 210.0, kWall = 120.0;
constexpr int kPixelsPerSquare = 120;  // Of a ChArUco board's drawing.

// What the board shows at a point (x, y) of its plane: -1 nothing (beyond the board and a white
// margin of one square around it), 0 white, 1 black.
class BoardPattern {
 public:
  explicit BoardPattern(const BoardSpec& board) : board_(board) {
    if (board.kind == BoardKind::kCharuco)
      CharucoBoardOf(board)->draw(cv::Size(board.cols * kPixelsPerSquare, board.rows * kPixelsPerSquare), drawing_);
  }

  int Colour(double x, double y) const {
    const double s = board_.square_m;
    const Eigen::Vector4d e = board_.Extent();
    if (x < e[0] - s || y < e[2] - s || x >= e[1] + s || y >= e[3] + s) return -1;
    if (x < e[0] || y < e[2] || x >= e[1] || y >= e[3]) return 0;
    if (board_.kind == BoardKind::kCharuco) {
      const int u = std::min(drawing_.cols - 1, static_cast<int>(x / s * kPixelsPerSquare));
      const int v = std::min(drawing_.rows - 1, static_cast<int>(y / s * kPixelsPerSquare));
      return drawing_.at<uint8_t>(v, u) < 128 ? 1 : 0;
    }
    // Checkerboard squares (i, j) = floor of (x, y) / s, from -1 to cols - 1: (0, 0) is black.
    const int i = static_cast<int>(std::floor(x / s)), j = static_cast<int>(std::floor(y / s));
    return ((i + j) & 1) == 0 ? 1 : 0;
  }

 private:
  BoardSpec board_;
  cv::Mat drawing_;  // A ChArUco board as OpenCV draws it, kPixelsPerSquare per square.
};

Eigen::Matrix3d Rotation(double rx, double ry, double rz) {
  return (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Whether the board is in view as a person calibrating holds it: a checkerboard whole (every inner
// corner and the board's outer corners inside the image, 8 px in); a ChArUco board, which is found
// in part, with two thirds of its inner corners inside (so that its corners reach the image's
// edges and corners). Every point in front of the camera, and inside the image only where the
// model maps it back.
bool InView(const CameraCalibration& camera, const BoardSpec& board, const SE3d& cam_from_board) {
  const bool part = board.kind == BoardKind::kCharuco;
  const Eigen::Vector4d e = board.Extent();
  std::vector<Eigen::Vector3d> points = board.Corners();
  const size_t inner = points.size();
  for (int k = 0; k < 4; ++k) points.emplace_back(e[k & 1], e[2 + (k >> 1)], 0.0);
  size_t inner_inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d c = cam_from_board * points[i];
    if (c.z() < 0.05) return false;
    Eigen::Vector2d n;
    const Eigen::Vector2d px = camera.Project(c);
    const bool inside = px.x() >= 8 && px.y() >= 8 && px.x() <= camera.width - 9 && px.y() <= camera.height - 9;
    if (!inside && !part) return false;
    if (!inside) continue;
    // A pixel the model projects to must also come back (the model is invertible there).
    if (!camera.Unproject(px, &n) || (n - c.head<2>() / c.z()).norm() > 1e-6) return false;
    if (i < inner) ++inner_inside;
  }
  return 3 * inner_inside >= 2 * inner;
}

}  // namespace

CameraCalibration ExampleCamera(CameraModel model) {
  CameraCalibration c;
  c.model = model;
  c.width = 640;
  c.height = 480;
  c.fx = 420.0, c.fy = 418.0, c.cx = 322.5, c.cy = 237.0;
  if (model == CameraModel::kEquidistant || model == CameraModel::kFov) c.fx = 300.0, c.fy = 299.0;
  c.distortion = synth::TypicalDistortion(model);
  c.Validate("ExampleCamera");
  return c;
}

BoardRenderer::BoardRenderer(const CameraCalibration& camera) : lens_(camera) {}

Image<uint8_t> BoardRenderer::Render(const BoardSpec& board, const SE3d& cam_from_board, double noise_sigma,
                                     uint32_t seed) const {
  const BoardPattern pattern(board);
  const SE3d board_from_cam = cam_from_board.Inverse();
  const Eigen::Matrix3d R = board_from_cam.So3().Matrix();
  const Eigen::Vector3d origin = board_from_cam.Translation();  // The camera centre in the board's frame.
  // What the ray through normalized coordinates n sees.
  const auto value_of = [&](const Eigen::Vector2d& n) {
    const Eigen::Vector3d dir = R * Eigen::Vector3d(n.x(), n.y(), 1.0);
    const double t = std::abs(dir.z()) > 1e-12 ? -origin.z() / dir.z() : -1.0;
    if (t <= 0.0) return kWall;
    const Eigen::Vector3d hit = origin + t * dir;
    const int colour = pattern.Colour(hit.x(), hit.y());
    return colour < 0 ? kWall : colour == 1 ? kBlack : kWhite;
  };
  const int width = lens_.width(), height = lens_.height();
  Image<float> albedo(width, height);
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      // The rays inside the pixel, from its corners' normalized coordinates (bilinear: the lens
      // bends a pixel's rays by a few millionths of one).
      const Eigen::Vector2d c00 = lens_.Corner(x, y).cast<double>(), c10 = lens_.Corner(x + 1, y).cast<double>(),
                            c01 = lens_.Corner(x, y + 1).cast<double>(),
                            c11 = lens_.Corner(x + 1, y + 1).cast<double>();
      if (!c00.allFinite() || !c10.allFinite() || !c01.allFinite() || !c11.allFinite()) {
        albedo(x, y) = static_cast<float>(kWall / 255.0);
        continue;
      }
      const auto mean_of = [&](int samples) {
        double sum = 0.0, first = -1.0;
        bool one_value = true;
        for (int sy = 0; sy < samples; ++sy)
          for (int sx = 0; sx < samples; ++sx) {
            const double a = (sx + 0.5) / samples, b = (sy + 0.5) / samples;
            const double value = value_of((1 - b) * ((1 - a) * c00 + a * c10) + b * ((1 - a) * c01 + a * c11));
            if (first < 0.0) first = value;
            one_value = one_value && value == first;
            sum += value;
          }
        return std::make_pair(sum / (samples * samples), one_value);
      };
      auto [mean, one_value] = mean_of(kCoarse);
      if (!one_value) mean = mean_of(kFine).first;
      albedo(x, y) = static_cast<float>(mean / 255.0);
    }
  });
  // The synthetic world's image formation at unit gain (a grey level per 1/255 of albedo).
  synth::FormationOptions formation;
  formation.noise_sigma = noise_sigma;
  formation.noise_seed = seed;
  return synth::FormImage(albedo, synth::Photometry{}, formation);
}

std::vector<SE3d> BoardViews(const CameraCalibration& camera, const BoardSpec& board, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector4d e = board.Extent();
  const double board_w = e[1] - e[0];
  const Eigen::Vector3d centre(0.5 * (e[0] + e[1]), 0.5 * (e[2] + e[3]), 0.0);
  std::vector<SE3d> views;
  for (int attempt = 0; static_cast<int>(views.size()) < count; ++attempt) {
    DSM_CHECK(attempt < 1000 * count, "board views: the board does not fit the image");
    // Its width across the image as a share, hence its distance (pinhole approximation).
    const double share = 0.35 + 0.4 * unit(rng);
    const double distance = camera.fx * board_w / (share * camera.width);
    // One draw after the other (the order of a call's arguments is the compiler's).
    const double at_y = camera.height * unit(rng);
    const double at_x = camera.width * unit(rng);
    Eigen::Vector2d n;
    if (!camera.Unproject({at_x, at_y}, &n)) continue;
    const Eigen::Vector3d position = distance * Eigen::Vector3d(n.x(), n.y(), 1.0).normalized();
    const double deg = M_PI / 180.0;
    const double turn = (2 * unit(rng) - 1) * 20 * deg;
    const double tilt_y = (2 * unit(rng) - 1) * 45 * deg;
    const double tilt_x = (2 * unit(rng) - 1) * 45 * deg;
    const Eigen::Matrix3d cam_R_board = Rotation(tilt_x, tilt_y, turn);
    // cam_from_board maps the board's centre to `position`.
    const SE3d cam_from_board(SO3d(cam_R_board), position - cam_R_board * centre);
    if (InView(camera, board, cam_from_board)) views.push_back(cam_from_board);
  }
  return views;
}

void WriteBoardSequence(const std::filesystem::path& dir, const CameraCalibration& camera, const BoardSpec& board,
                        int count, uint32_t seed) {
  std::filesystem::create_directories(dir / "images");
  const std::vector<SE3d> views = BoardViews(camera, board, count, seed);
  std::vector<FrameRecord> frames(views.size());
  const BoardRenderer renderer(camera);
  for (size_t i = 0; i < views.size(); ++i)
    WriteGray8(dir / "images" / FolderImageName(i), renderer.Render(board, views[i], 1.0, seed * 1000 + i));
  for (size_t i = 0; i < views.size(); ++i) {
    frames[i].t_ns = static_cast<int64_t>(i) * 100000000;
    frames[i].exposure_ms = 0.0;
  }
  WriteFolderTimes(dir, frames);
  CameraYaml yaml;
  yaml.camera = camera;
  yaml.rate_hz = 10.0;
  WriteCameraYaml(dir / "camera.yaml", yaml);
}

}  // namespace dsm

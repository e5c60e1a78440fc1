// SPDX-License-Identifier: MIT
// Geometric calibration of a camera from views of a checkerboard or a ChArUco board (board.h), for
// every camera model dsm reads (geometry/camera.h): pinhole, radtan (k1 k2 p1 p2), equidistant
// (k1..k4) and fov (w).
//
//   1. Frames: every image of a folder (its images/ when there is one) or frame of a video.
//   2. Detection (detect.h): a checkerboard whole, a ChArUco board whole or in part.
//   3. Views: the sharp ones (the median width of the board's edges under 3 px), at most `max_views`,
//      picked greedily to differ most in where the board lies in the image, how large it is and
//      how it is tilted (not 300 copies of one pose).
//   4. Calibration: OpenCV's calibrateCamera (fisheye::calibrate for equidistant; fov starts from
//      the equidistant solution) as the start, then every parameter and pose refined by Ceres
//      with dsm's own camera model (refine.h). Corners whose reprojection error exceeds 5x the
//      median corner's (and 0.25 px), then views whose RMS exceeds 3x the median view's (and
//      0.5 px) or that keep too few corners, are dropped and the rest calibrated again, once.
//   5. What it says: the RMS per view and overall, the cells of a 3x3 grid over the image that no
//      corner covered, and the parameters whose standard deviation (from the covariance at the
//      solution) is large (focal lengths over 0.5%, the principal point over 5 px).
// Throws InputError (a clear message, no calibration) when the board is never found, fewer than
// kMinViews views are usable, or the focal length is left unconstrained.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "dsm/calibration/board.h"
#include "dsm/geometry/camera.h"

namespace dsm {

struct CalibrationOptions {
  BoardSpec board;
  CameraModel model = CameraModel::kRadTan;
  int max_views = 40;
};

struct CalibrationView {
  int frame = -1;        // Index among the input's frames.
  int corners = 0;       // Of the board's inner corners, found.
  double rms_px = 0.0;   // Reprojection RMS of its corners at the solution (0: not used).
  int corners_dropped = 0;  // Of its corners, outliers left out.
  bool used = false;     // Calibrated with (else: not picked, or dropped as an outlier).
  std::string why_not;   // When not used.
};

struct CalibrationResult {
  CameraCalibration camera;
  double rms_px = 0.0;
  int frames = 0;  // Read.
  std::vector<CalibrationView> views;  // Every frame the board was found in.
  int views_used = 0;
  std::vector<std::string> uncovered;  // Cells of the image no corner covered ("top-left", ...).
  std::vector<std::string> weak;       // Poorly constrained parameters, with their deviation.
};

constexpr int kMinViews = 6;

// The frames of `input` (a folder of images, a folder with images/, or a video file), 8-bit grey.
CalibrationResult Calibrate(const std::filesystem::path& input, const CalibrationOptions& options);

}  // namespace dsm
